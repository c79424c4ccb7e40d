# SPDX-License-Identifier: GPL-3.0-or-later
# The Debian package: what `cmake --install` adds for it (the bundled brain, the copyright file and the
# changelog) and CPack's DEB settings. `.ci/package` configures the Debian layout (lib/<multiarch>,
# lib/python3/dist-packages) and runs cpack, which writes build/package/dtfabric_VERSION_ARCH.deb with
# Depends computed from the binaries by dpkg-shlibdeps.
if(NOT DTF_INSTALL OR NOT DTF_BUILD_APPS)
  return()
endif()

set(DTF_PACKAGE_MAINTAINER "dtfabric maintainers <maintainers@dtfabric.invalid>" CACHE STRING
    "the Debian package's Maintainer field (also the changelog's signature)")

# The bundled brain (dtfabric render /usr/share/dtfabric/dwi.nii.gz) with its provenance and license.
install(FILES ${PROJECT_SOURCE_DIR}/sample_data/dwi.nii.gz ${PROJECT_SOURCE_DIR}/sample_data/dwi.bval
              ${PROJECT_SOURCE_DIR}/sample_data/dwi.bvec ${PROJECT_SOURCE_DIR}/sample_data/README.md
        DESTINATION ${CMAKE_INSTALL_DATADIR}/dtfabric)

# /usr/share/doc/dtfabric/{copyright,changelog.gz} (a native package: the version has no Debian revision).
set(_debian ${PROJECT_BINARY_DIR}/debian)
configure_file(${PROJECT_SOURCE_DIR}/cmake/debian/changelog.in ${_debian}/changelog @ONLY)
execute_process(COMMAND gzip -9nc ${_debian}/changelog OUTPUT_FILE ${_debian}/changelog.gz RESULT_VARIABLE _rc)
if(NOT _rc EQUAL 0)
  message(FATAL_ERROR "gzip of the Debian changelog failed")
endif()
install(FILES ${PROJECT_SOURCE_DIR}/cmake/debian/copyright ${_debian}/changelog.gz
        DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/dtfabric)

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME dtfabric)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_DIRECTORY ${PROJECT_BINARY_DIR}/package)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
set(CPACK_INSTALL_DEFAULT_DIRECTORY_PERMISSIONS
    OWNER_READ OWNER_WRITE OWNER_EXECUTE GROUP_READ GROUP_EXECUTE WORLD_READ WORLD_EXECUTE)
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "fabric-like tensor LIC viewer for diffusion MRI")
# Lines under 80 characters (Debian policy 3.4.1).
set(CPACK_PACKAGE_DESCRIPTION
    "dtfabric shows diffusion-tensor MRI as a woven texture on a surface whose\n"
    "threads follow the tensor's two in-surface directions, in the medical RGB\n"
    "colour code: the image-space tensor LIC of Eichelbaum, Hlawitschka, Hamann\n"
    "and Scheuermann. It reads tensors, DWIs with their gradient tables, fibre\n"
    "sets and tractograms, renders headless through EGL, checks gradient\n"
    "orientation, runs as a BIDS App and opens an interactive viewer.\n"
    "\n"
    "This package holds the dtfabric command with its man pages and bash\n"
    "completion, the shared library libdtfabric with its headers and CMake\n"
    "package, the Python module dtfabric and a real sample brain under\n"
    "/usr/share/dtfabric.")
string(REPLACE ";" "" CPACK_PACKAGE_DESCRIPTION "${CPACK_PACKAGE_DESCRIPTION}")
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "${DTF_PACKAGE_MAINTAINER}")
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# libdtfabric's shlibs file and the ldconfig trigger.
set(CPACK_DEBIAN_PACKAGE_GENERATE_SHLIBS ON)
set(CPACK_DEBIAN_PACKAGE_GENERATE_SHLIBS_POLICY ">=")
# The ldconfig trigger Debian wants for a public shared library (CPack's postinst/postrm also call ldconfig).
set(CPACK_DEBIAN_PACKAGE_CONTROL_EXTRA ${PROJECT_SOURCE_DIR}/cmake/debian/triggers)
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
# What the binaries do not say: libepoxy opens libEGL at run time, headless rendering needs a GL driver
# (Mesa's llvmpipe without a GPU), the figures' text and the viewer's panels are DejaVu Sans (fontconfig finds
# it for the profile figures), the Python module needs the interpreter it was built for and numpy.
set(_depends "libegl1, libgl1-mesa-dri, fonts-dejavu-core")
if(DTF_PYTHON_MODULE)
  string(REPLACE "." ";" _pv "${DTF_PYTHON_VERSION}")
  list(GET _pv 0 _pmajor)
  list(GET _pv 1 _pminor)
  math(EXPR _pnext "${_pminor} + 1")
  string(APPEND _depends ", python3 (>= ${_pmajor}.${_pminor}~), python3 (<< ${_pmajor}.${_pnext}), python3-numpy")
  set(CPACK_DEBIAN_PACKAGE_SUGGESTS "python3-nibabel")
endif()
set(CPACK_DEBIAN_PACKAGE_DEPENDS "${_depends}")
include(CPack)
