# Tests of the viewer area: script parser and panels (unit), the command without a display (cli), the
# window under Xvfb (window).
dtf_test(test_view_script SOURCES unit/view_script_test.cpp LIBS dtf_view_script)
dtf_test(test_view_ui SOURCES unit/view_ui_test.cpp LIBS dtf_ui)
dtf_test(test_view_cli SOURCES window/view_cli_test.cpp LIBS dtf_model)
dtf_test(test_view_window SOURCES window/view_window_test.cpp LIBS dtf_io dtf_model)
dtf_test(test_view_scene SOURCES gl/view_scene_alloc_test.cpp LIBS dtf_viewer)
dtf_test(test_view_tracts SOURCES gl/view_tracts_test.cpp LIBS dtf_viewer)
dtf_test(test_help_cli SOURCES cli/help_cli_test.cpp LIBS dtf_cli)
dtf_test(test_view_initial_view SOURCES gl/view_initial_view_test.cpp LIBS dtf_viewer)
dtf_test(test_view_tract_colouring SOURCES gl/view_tract_colouring_test.cpp LIBS dtf_viewer)
dtf_test(test_view_tract_colouring_window SOURCES window/view_tract_colouring_window_test.cpp LIBS dtf_io dtf_model)
# The session library without a window or GL context: the generic worker, the session, its layering.
dtf_test(test_coalescing_worker SOURCES unit/coalescing_worker_test.cpp LIBS dtf_model)
dtf_test(test_viewer_session SOURCES unit/viewer_session_test.cpp LIBS dtf_scene)
dtf_test(test_scene_layering SOURCES unit/scene_layering_test.cpp LIBS dtf_model)
dtf_test(test_view_fibres_window SOURCES window/view_fibres_window_test.cpp LIBS dtf_io dtf_model)
dtf_test(test_tract_overlay_rule SOURCES unit/tract_overlay_rule_test.cpp LIBS dtf_scene)
dtf_test(test_view_fibres_scene SOURCES gl/view_fibres_scene_test.cpp LIBS dtf_viewer)
