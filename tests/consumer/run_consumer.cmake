# SPDX-License-Identifier: GPL-3.0-or-later
# The package_consumer test: installs the build into a fresh prefix, configures tests/consumer against it
# (find_package(dtfabric) through CMAKE_PREFIX_PATH only, same compiler, Release), builds it with every
# installed header compiled on its own, and runs the consumer on the real data.
# cmake -DBUILD_DIR=... -DSOURCE_DIR=... -DWORK_DIR=... -DCXX_COMPILER=... [-DLAUNCHER=...] -P run_consumer.cmake
foreach(v BUILD_DIR SOURCE_DIR WORK_DIR CXX_COMPILER)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "run_consumer.cmake: ${v} not given")
  endif()
endforeach()

function(step name)
  string(TIMESTAMP t0 "%s")
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  string(TIMESTAMP t1 "%s")
  math(EXPR dt "${t1} - ${t0}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${name} failed (${rc}):\n${out}")
  endif()
  message("-- ${name}: ${dt} s")
  set(step_output "${out}" PARENT_SCOPE)
endfunction()

set(prefix ${WORK_DIR}/prefix)
set(build ${WORK_DIR}/build)
file(REMOVE_RECURSE ${prefix})
# The consumer's build folder stays between runs (only its sources and the prefix change): a rerun
# configures and compiles again, with ccache when the build uses it.
file(REMOVE ${build}/CMakeCache.txt)

step("install" ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
set(launcher "")
if(LAUNCHER)
  set(launcher -DCMAKE_CXX_COMPILER_LAUNCHER=${LAUNCHER})
endif()
step("configure consumer" ${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/consumer -B ${build}
  -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=${CXX_COMPILER} ${launcher}
  -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_FIND_PACKAGE_NO_PACKAGE_REGISTRY=ON -DCONSUMER_CHECK_HEADERS=ON)
message("${step_output}")
# The package must come from the prefix, not from the build or source tree.
file(STRINGS ${build}/CMakeCache.txt found REGEX "^dtfabric_DIR:")
if(NOT found MATCHES "=${prefix}/")
  message(FATAL_ERROR "dtfabric was not found in ${prefix}: ${found}")
endif()
step("build consumer and header checks" ${CMAKE_COMMAND} --build ${build} -j2)

set(data $ENV{DTF_SHARED_DATA})
if(NOT data)
  set(data ${SOURCE_DIR}/../shared/data)
endif()
string(TIMESTAMP t0 "%s")
execute_process(COMMAND ${build}/dtfabric_consumer ${data} ${SOURCE_DIR}/tests/baseline/images/consumer_sphere.png
                        ${WORK_DIR}/output
                RESULT_VARIABLE rc)
string(TIMESTAMP t1 "%s")
math(EXPR dt "${t1} - ${t0}")
message("-- run consumer: ${dt} s")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "dtfabric_consumer failed (${rc}); its images are in ${WORK_DIR}/output")
endif()
