# Tests of surfaces/ (dtf_test(...) lines; the label follows from each file's suffix).
dtf_test(test_orientation_check SOURCES surfaces/orientation_check_test.cpp LIBS dtf_surfaces dtf_io dtf_model)
dtf_test(test_fibre_orientation_check SOURCES surfaces/fibre_orientation_check_test.cpp LIBS dtf_surfaces dtf_io dtf_model)
dtf_test(test_fibre_agreement SOURCES surfaces/fibre_agreement_test.cpp LIBS dtf_surfaces dtf_io dtf_model)
dtf_test(test_surfaces SOURCES surfaces/surfaces_test.cpp LIBS dtf_surfaces dtf_model)
dtf_test(test_fibre_surface SOURCES surfaces/fibre_surface_test.cpp LIBS dtf_surfaces dtf_model)
dtf_test(test_mesh_checks SOURCES surfaces/mesh_checks_test.cpp LIBS dtf_surfaces dtf_model)
dtf_test(test_tract_tracking SOURCES surfaces/tract_tracking_test.cpp LIBS dtf_surfaces dtf_io dtf_model)
dtf_test(test_tract_agreement SOURCES surfaces/tract_agreement_test.cpp LIBS dtf_surfaces dtf_io dtf_model)
