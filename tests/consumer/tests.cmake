# SPDX-License-Identifier: GPL-3.0-or-later
# The installable package. package_consumer installs this build into a fresh prefix and builds and runs
# tests/consumer against it (its own EGL context, real data, a baseline image, the host's GL state).
# package_subdirectory configures a host project that adds dtfabric with add_subdirectory().
# Not under the sanitizers: the consumer would need their runtime.
if(NOT DTF_SANITIZE AND NOT DTF_SANITIZE_THREAD)
  add_test(NAME package_consumer
    COMMAND ${CMAKE_COMMAND} -DBUILD_DIR=${PROJECT_BINARY_DIR} -DSOURCE_DIR=${PROJECT_SOURCE_DIR}
            -DWORK_DIR=${PROJECT_BINARY_DIR}/test_scratch/package_consumer -DCXX_COMPILER=${CMAKE_CXX_COMPILER}
            -DLAUNCHER=${CMAKE_CXX_COMPILER_LAUNCHER} -P ${PROJECT_SOURCE_DIR}/tests/consumer/run_consumer.cmake)
  set_tests_properties(package_consumer PROPERTIES LABELS "package;gl;baseline" TIMEOUT 900 PROCESSORS 2
    SKIP_REGULAR_EXPRESSION "dtfabric_consumer: SKIPPED")
endif()

# Configure only (building would compile the library a second time with the host's flags).
add_test(NAME package_subdirectory
  COMMAND ${CMAKE_COMMAND} --fresh -S ${PROJECT_SOURCE_DIR}/tests/consumer/subdirectory
          -B ${PROJECT_BINARY_DIR}/test_scratch/package_subdirectory -DCMAKE_BUILD_TYPE=RelWithDebInfo
          -DCMAKE_CXX_COMPILER=${CMAKE_CXX_COMPILER} -DCMAKE_C_COMPILER=${CMAKE_C_COMPILER}
          -DDTF_SOURCE=${PROJECT_SOURCE_DIR} -DDTF_WERROR=ON)
set_tests_properties(package_subdirectory PROPERTIES LABELS "package;unit" TIMEOUT 300)
