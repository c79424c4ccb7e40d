# SPDX-License-Identifier: GPL-3.0-or-later
# The Debian package (.ci/package builds it from this build; .ci/test does so before ctest): its files,
# fields, dependencies, the binary and the Python module run from the extracted package, lintian. Skipped
# when the package was not built, unless DTF_REQUIRE_TOOLS=1.
if(DTF_INSTALL AND DTF_PYTHON_MODULE AND NOT DTF_SANITIZE AND NOT DTF_SANITIZE_THREAD)
  add_test(NAME package_deb COMMAND ${CMAKE_CURRENT_SOURCE_DIR}/package/check_deb.sh ${PROJECT_BINARY_DIR}
                                    ${PROJECT_SOURCE_DIR} ${PROJECT_VERSION} ${DTF_PYTHON_EXECUTABLE})
  set_tests_properties(package_deb PROPERTIES LABELS "package;gl" TIMEOUT 600 SKIP_RETURN_CODE 77)
endif()
