# SPDX-License-Identifier: GPL-3.0-or-later
# Tests of io/diffusion/ (dtf_test(...) lines; the label follows from each file's suffix).
dtf_test(test_fit_gradients SOURCES io/diffusion/fit_gradients_test.cpp LIBS dtf_io)
dtf_test(test_fit_tensor SOURCES io/diffusion/fit_tensor_test.cpp LIBS dtf_io)
dtf_test(test_fit_real_data SOURCES io/diffusion/fit_real_data_test.cpp LIBS dtf_io)
dtf_test(test_bootstrap SOURCES io/diffusion/bootstrap_test.cpp LIBS dtf_io)
dtf_test(test_bedpostx_samples SOURCES io/diffusion/bedpostx_samples_test.cpp LIBS dtf_io)
