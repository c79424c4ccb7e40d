# SPDX-License-Identifier: GPL-3.0-or-later
# cmake -DEXE=path/to/dtfabric -DOUT=dir -P dtf_write_manual.cmake: OUT/man1/NAME.1.gz for every page the
# executable names (`dtfabric help --man-pages`), compressed with gzip -9n (no name or time stamp, as
# Debian wants), and OUT/completions/dtfabric. Replaces what an earlier run wrote.
foreach(v EXE OUT)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "dtf_write_manual.cmake: ${v} not given")
  endif()
endforeach()
find_program(GZIP gzip REQUIRED)

function(run_exe output)
  execute_process(COMMAND ${EXE} help ${ARGN} OUTPUT_FILE ${output} RESULT_VARIABLE rc ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "dtfabric help ${ARGN} failed (${rc}): ${err}")
  endif()
endfunction()

file(REMOVE_RECURSE ${OUT}/man1 ${OUT}/completions)
file(MAKE_DIRECTORY ${OUT}/man1 ${OUT}/completions)
run_exe(${OUT}/pages.txt --man-pages)
file(STRINGS ${OUT}/pages.txt pages)
file(REMOVE ${OUT}/pages.txt)
foreach(page IN LISTS pages)
  run_exe(${OUT}/man1/${page}.1 --man ${page})
  execute_process(COMMAND ${GZIP} -9nf ${OUT}/man1/${page}.1 RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "gzip of ${page}.1 failed")
  endif()
endforeach()
run_exe(${OUT}/completions/dtfabric --bash-completion)
file(TOUCH ${OUT}/stamp)
