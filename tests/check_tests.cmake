# Tests of the orientation check (dtf_test(...) lines).
dtf_test(test_orientation_check LABEL unit SOURCES unit/orientation_check_test.cpp LIBS dtf_surfaces dtf_io dtf_model)
dtf_test(test_check_sheet LABEL baseline SOURCES gl/check_sheet_test.cpp LIBS dtf_app)
dtf_test(test_check_cli LABEL cli SOURCES cli/check_cli_test.cpp LIBS dtf_io dtf_model)
dtf_test(test_bitmap_text LABEL unit SOURCES unit/bitmap_text_test.cpp LIBS dtf_render dtf_model)
dtf_test(test_orientation_banner LABEL unit SOURCES unit/orientation_banner_test.cpp LIBS dtf_ui)
dtf_test(test_viewer_orientation LABEL gl SOURCES gl/viewer_orientation_test.cpp LIBS dtf_app)
