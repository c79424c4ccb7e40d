# SPDX-License-Identifier: GPL-3.0-or-later
# Finds every third-party dependency from Debian 12 packages and defines imported targets for the ones
# whose packaging is incomplete (nifticlib, imgui backends, epoxy/egl). GLFW and ImGui only for the apps.
find_package(PkgConfig REQUIRED)
find_package(Threads REQUIRED)
find_package(ZLIB REQUIRED)
find_package(PNG REQUIRED)
find_package(glm REQUIRED)
if(NOT TARGET glm::glm)
  add_library(glm::glm INTERFACE IMPORTED)
endif()

# Debian 12's NIFTIConfig.cmake is broken: locate nifticlib by hand. libnifti2 reads NIfTI-1 and NIfTI-2.
find_path(NIFTI_INCLUDE_DIR nifti2_io.h PATH_SUFFIXES nifti REQUIRED)
find_library(NIFTI2_LIBRARY nifti2 REQUIRED)
find_library(ZNZ_LIBRARY znz REQUIRED)
add_library(dtf_nifti INTERFACE)
target_include_directories(dtf_nifti SYSTEM INTERFACE ${NIFTI_INCLUDE_DIR})
target_link_libraries(dtf_nifti INTERFACE ${NIFTI2_LIBRARY} ${ZNZ_LIBRARY} ZLIB::ZLIB m)

find_package(VTK 9 REQUIRED COMPONENTS
  CommonCore CommonDataModel CommonExecutionModel FiltersCore FiltersGeneral FiltersModeling
  FiltersSources FiltersGeometry IOGeometry IOPLY IOLegacy IOXML ImagingCore ImagingGeneral)

find_package(CGAL REQUIRED)

# gzip inflation of whole buffers for the readers (.nii.gz, .mif.gz, .trk.gz, NRRD gzip, zip entries).
pkg_check_modules(LIBDEFLATE REQUIRED IMPORTED_TARGET libdeflate)
# Every JSON document read or written (header-only; private to the libraries that use it).
find_package(nlohmann_json 3 REQUIRED)

pkg_check_modules(EPOXY REQUIRED IMPORTED_TARGET epoxy)
# 2D figures with real text (profile plots, figure text): Cairo draws PNG and SVG, Pango lays out the text.
pkg_check_modules(CAIRO REQUIRED IMPORTED_TARGET cairo)
pkg_check_modules(PANGOCAIRO REQUIRED IMPORTED_TARGET pangocairo)
pkg_check_modules(EGL REQUIRED IMPORTED_TARGET egl)
# The figures' text: DejaVu Sans rasterised by FreeType (private to dtf_render).
pkg_check_modules(FREETYPE REQUIRED IMPORTED_TARGET freetype2)
find_file(DTF_FONT_FILE DejaVuSans.ttf PATHS /usr/share/fonts/truetype/dejavu NO_DEFAULT_PATH)
if(NOT DTF_FONT_FILE)
  message(FATAL_ERROR "DejaVuSans.ttf not found in /usr/share/fonts/truetype/dejavu (package fonts-dejavu-core); "
    "set DTF_FONT_FILE to another copy")
endif()

# The window, the panels and the executable only (DTF_BUILD_APPS).
if(DTF_BUILD_APPS)
  find_package(glfw3 REQUIRED)
  # Debian's imgui ships the core as libimgui.a and the backends as sources in its examples folder.
  pkg_check_modules(IMGUI REQUIRED IMPORTED_TARGET imgui)
  # The desktop's file dialog through the XDG desktop portal (the viewer falls back to its own without one).
  pkg_check_modules(LIBPORTAL REQUIRED IMPORTED_TARGET libportal)
  set(DTF_IMGUI_BACKENDS_DIR /usr/share/doc/libimgui-dev/examples/backends CACHE PATH "imgui backend sources")
  if(NOT EXISTS ${DTF_IMGUI_BACKENDS_DIR}/imgui_impl_glfw.cpp)
    message(FATAL_ERROR "imgui backend sources not found in ${DTF_IMGUI_BACKENDS_DIR} (package libimgui-dev)")
  endif()
endif()

if(DTF_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()
