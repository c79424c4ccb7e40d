# Tests of the tracts area: tract files, tracking, tract/fabric agreement and the track/compare commands.
dtf_test(test_tract_io SOURCES unit/tract_io_test.cpp LIBS dtf_scene dtf_surfaces dtf_io dtf_model)
dtf_test(test_tract_tracking SOURCES unit/tract_tracking_test.cpp LIBS dtf_surfaces dtf_io dtf_model)
dtf_test(test_tract_agreement SOURCES unit/tract_agreement_test.cpp LIBS dtf_surfaces dtf_io dtf_model)
dtf_test(test_tract_cli SOURCES cli/tract_cli_test.cpp LIBS dtf_model)
