# SPDX-License-Identifier: GPL-3.0-or-later
# Tests of surfaces/ itself (dtf_test(...) lines; the label follows from each file's suffix). The subfolders
# have their own lists: surfaces/tracking, surfaces/analyses.
dtf_test(test_surfaces SOURCES surfaces/surfaces_test.cpp LIBS dtf_surfaces dtf_model)
dtf_test(test_fibre_surface SOURCES surfaces/fibre_surface_test.cpp LIBS dtf_surfaces dtf_model)
dtf_test(test_mesh_checks SOURCES surfaces/mesh_checks_test.cpp LIBS dtf_surfaces dtf_model)
dtf_test(test_isosurface_smoothing SOURCES surfaces/isosurface_smoothing_test.cpp LIBS dtf_surfaces dtf_model)
