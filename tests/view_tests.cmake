# Tests of the viewer area: script parser and panels (unit), the command without a display (cli), the
# window under Xvfb (window).
dtf_test(test_view_script LABEL unit SOURCES unit/view_script_test.cpp LIBS dtf_viewer)
dtf_test(test_view_ui LABEL unit SOURCES unit/view_ui_test.cpp LIBS dtf_ui)
dtf_test(test_view_cli LABEL cli SOURCES window/view_cli_test.cpp LIBS dtf_model)
dtf_test(test_view_window LABEL window SOURCES window/view_window_test.cpp LIBS dtf_io dtf_model)
dtf_test(test_view_scene LABEL gl SOURCES unit/view_scene_alloc_test.cpp LIBS dtf_viewer)
dtf_test(test_view_tracts LABEL gl SOURCES gl/view_tracts_test.cpp LIBS dtf_viewer)
dtf_test(test_help_cli LABEL cli SOURCES cli/help_cli_test.cpp LIBS dtf_cli)
dtf_test(test_view_initial_view LABEL gl SOURCES gl/view_initial_view_test.cpp LIBS dtf_viewer)
