# Tests of the surfaces area.
dtf_test(test_surfaces SOURCES unit/surfaces_test.cpp LIBS dtf_surfaces dtf_model)
dtf_test(test_fibre_surface SOURCES unit/fibre_surface_test.cpp LIBS dtf_surfaces dtf_model)
dtf_test(test_mesh_checks SOURCES unit/mesh_checks_test.cpp LIBS dtf_surfaces dtf_model)
dtf_test(test_surface_cli SOURCES cli/surface_cli_test.cpp LIBS dtf_model)
dtf_test(test_medical_brain SOURCES gl/medical_brain_test.cpp LIBS dtf_render dtf_io dtf_surfaces dtf_model)
dtf_test(test_surface_spec SOURCES unit/surface_spec_test.cpp LIBS dtf_scene)
