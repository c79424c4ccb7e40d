# Tests of the fit area (dtf_test(...) lines).
dtf_test(test_fit_gradients SOURCES unit/fit_gradients_test.cpp LIBS dtf_io)
dtf_test(test_fit_tensor SOURCES unit/fit_tensor_test.cpp LIBS dtf_io)
dtf_test(test_fit_real_data SOURCES unit/fit_real_data_test.cpp LIBS dtf_io)
dtf_test(test_fit_cli SOURCES cli/fit_cli_test.cpp LIBS dtf_io)
