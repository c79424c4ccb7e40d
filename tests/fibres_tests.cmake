# Tests of crossing-fibre sets (io/model/fibre_set.h, io/fibre_io.h, the multi-population fabric).
dtf_test(test_fibres LABEL unit SOURCES unit/fibre_io_test.cpp LIBS dtf_io)
dtf_test(test_fibres_render LABEL gl SOURCES gl/fibre_render_test.cpp LIBS dtf_render dtf_io dtf_model)
dtf_test(test_fibres_brain LABEL baseline SOURCES gl/fibre_brain_test.cpp LIBS dtf_render dtf_surfaces dtf_io dtf_model)
dtf_test(test_fibres_cli LABEL cli SOURCES cli/fibre_cli_test.cpp LIBS dtf_io)
