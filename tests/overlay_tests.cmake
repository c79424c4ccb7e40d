# Tests of the tract overlay and split views (dtf_test(...) lines).
dtf_test(test_tract_overlay LABEL gl SOURCES gl/tract_overlay_test.cpp LIBS dtf_render dtf_model)
dtf_test(test_tract_overlay_select LABEL unit SOURCES unit/tract_overlay_select_test.cpp LIBS dtf_scene)
dtf_test(test_tract_overlay_baseline LABEL baseline SOURCES gl/tract_baseline_test.cpp LIBS dtf_render dtf_io dtf_model)
dtf_test(test_tract_overlay_cli LABEL cli SOURCES gl/tract_cli_test.cpp LIBS dtf_render dtf_io dtf_model)
dtf_test(test_tract_lod LABEL unit SOURCES unit/tract_lod_test.cpp LIBS dtf_render dtf_model)
dtf_test(test_tract_layer LABEL gl SOURCES gl/tract_layer_test.cpp LIBS dtf_render dtf_model)
