# Tests of the render area (dtf_test(...) lines).
