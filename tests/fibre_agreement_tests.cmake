# Tract agreement against crossing-fibre sets (surfaces/agreement.h) and `dtfabric compare` with a fibre set.
dtf_test(test_fibre_agreement SOURCES unit/fibre_agreement_test.cpp LIBS dtf_surfaces dtf_io dtf_model)
dtf_test(test_fibre_compare_cli SOURCES cli/fibre_compare_cli_test.cpp LIBS dtf_io dtf_model)
