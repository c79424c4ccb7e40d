# Tests of the tract overlay and split views (dtf_test(...) lines).
dtf_test(test_tract_overlay SOURCES gl/tract_overlay_test.cpp LIBS dtf_render dtf_model)
dtf_test(test_tract_overlay_select SOURCES unit/tract_overlay_select_test.cpp LIBS dtf_scene)
dtf_test(test_tract_overlay_baseline SOURCES gl/tract_baseline_test.cpp LIBS dtf_render dtf_io dtf_model)
dtf_test(test_tract_overlay_cli SOURCES gl/tract_cli_test.cpp LIBS dtf_render dtf_io dtf_model)
dtf_test(test_tract_lod SOURCES unit/tract_lod_test.cpp LIBS dtf_render dtf_model)
dtf_test(test_tract_layer SOURCES gl/tract_layer_test.cpp LIBS dtf_render dtf_model)
