# SPDX-License-Identifier: GPL-3.0-or-later
# The man pages (dtfabric(1), dtfabric-COMMAND(1)) and the bash completion, written at build time by the
# dtfabric executable from its command list and option tables (app/cli/manual.h), so they cannot drift
# from the parser. They land in ${PROJECT_BINARY_DIR}/manual/{man1/*.1.gz,completions/dtfabric} and are
# installed under share/man/man1 and share/bash-completion/completions.
set(DTF_MANUAL_DIR ${PROJECT_BINARY_DIR}/manual)
add_custom_command(OUTPUT ${DTF_MANUAL_DIR}/stamp
  COMMAND ${CMAKE_COMMAND} -DEXE=$<TARGET_FILE:dtfabric> -DOUT=${DTF_MANUAL_DIR}
          -P ${PROJECT_SOURCE_DIR}/cmake/dtf_write_manual.cmake
  DEPENDS dtfabric ${PROJECT_SOURCE_DIR}/cmake/dtf_write_manual.cmake
  COMMENT "Writing the man pages and the bash completion from the option tables"
  VERBATIM)
add_custom_target(dtf_manual ALL DEPENDS ${DTF_MANUAL_DIR}/stamp)

if(DTF_INSTALL)
  install(DIRECTORY ${DTF_MANUAL_DIR}/man1 DESTINATION ${CMAKE_INSTALL_MANDIR})
  install(FILES ${DTF_MANUAL_DIR}/completions/dtfabric
          DESTINATION ${CMAKE_INSTALL_DATADIR}/bash-completion/completions)
endif()
