# Tests of the io area (dtf_test(...) lines).
