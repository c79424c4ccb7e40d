# Tests of the fit area (dtf_test(...) lines).
