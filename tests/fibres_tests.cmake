# Tests of crossing-fibre sets (io/model/fibre_set.h, io/fibre_io.h, the multi-population fabric).
dtf_test(test_fibres SOURCES unit/fibre_io_test.cpp LIBS dtf_io)
dtf_test(test_fibres_render SOURCES gl/fibre_render_test.cpp LIBS dtf_render dtf_io dtf_model)
dtf_test(test_fibres_brain SOURCES gl/fibre_brain_baseline_test.cpp LIBS dtf_render dtf_surfaces dtf_io dtf_model)
dtf_test(test_fibres_cli SOURCES cli/fibre_cli_test.cpp LIBS dtf_io)
dtf_test(test_fibres_tools SOURCES gl/fibre_tools_baseline_test.cpp LIBS dtf_render dtf_surfaces dtf_io dtf_model)
dtf_test(test_fibres_tools_cli SOURCES cli/fibre_tools_cli_test.cpp LIBS dtf_io)
