# Tests of `dtfabric bids` (the BIDS App, its group report and the Snakemake workflow).
dtf_test(test_bids SOURCES unit/bids_test.cpp LIBS dtf_io dtf_model)
dtf_test(test_bids_cli SOURCES cli/bids_cli_test.cpp LIBS dtf_io dtf_model)
