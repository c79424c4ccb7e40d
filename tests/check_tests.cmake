# Tests of the orientation check (dtf_test(...) lines).
dtf_test(test_orientation_check SOURCES unit/orientation_check_test.cpp LIBS dtf_surfaces dtf_io dtf_model)
dtf_test(test_check_sheet SOURCES gl/check_sheet_baseline_test.cpp LIBS dtf_scene)
dtf_test(test_check_cli SOURCES cli/check_cli_test.cpp LIBS dtf_io dtf_model)
dtf_test(test_bitmap_text SOURCES unit/bitmap_text_test.cpp LIBS dtf_render dtf_model)
dtf_test(test_orientation_banner SOURCES unit/orientation_banner_test.cpp LIBS dtf_ui)
dtf_test(test_viewer_orientation SOURCES gl/viewer_orientation_test.cpp LIBS dtf_viewer)
dtf_test(test_fibre_orientation_check SOURCES unit/fibre_orientation_check_test.cpp LIBS dtf_surfaces dtf_io dtf_model)
dtf_test(test_fibre_check_cli SOURCES cli/fibre_check_cli_test.cpp LIBS dtf_io dtf_model)
