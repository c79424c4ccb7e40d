# SPDX-License-Identifier: GPL-3.0-or-later
# Tests of io/model/ (dtf_test(...) lines; the label follows from each file's suffix).
dtf_test(test_tensor SOURCES io/model/tensor_test.cpp LIBS dtf_model)
dtf_test(test_geometry SOURCES io/model/geometry_test.cpp LIBS dtf_model)
