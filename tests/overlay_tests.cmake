# Tests of the tract overlay and split views (dtf_test(...) lines).
dtf_test(test_tract_overlay LABEL gl SOURCES gl/tract_overlay_test.cpp LIBS dtf_render dtf_model)
