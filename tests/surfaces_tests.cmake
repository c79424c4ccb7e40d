# Tests of the surfaces area (dtf_test(...) lines).
