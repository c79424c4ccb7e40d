# Tests of the fit area (dtf_test(...) lines).
dtf_test(test_fit_gradients LABEL unit SOURCES unit/fit_gradients_test.cpp LIBS dtf_io)
dtf_test(test_fit_tensor LABEL unit SOURCES unit/fit_tensor_test.cpp LIBS dtf_io)
dtf_test(test_fit_real_data LABEL unit SOURCES unit/fit_real_data_test.cpp LIBS dtf_io)
dtf_test(test_fit_cli LABEL cli SOURCES cli/fit_cli_test.cpp LIBS dtf_io)
