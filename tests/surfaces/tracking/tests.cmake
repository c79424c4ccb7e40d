# SPDX-License-Identifier: GPL-3.0-or-later
# Tests of surfaces/tracking/ (dtf_test(...) lines; the label follows from each file's suffix).
dtf_test(test_tract_tracking SOURCES surfaces/tracking/tract_tracking_test.cpp LIBS dtf_surfaces dtf_io dtf_model)
dtf_test(test_tracking_parameters SOURCES surfaces/tracking/tracking_parameters_test.cpp LIBS dtf_surfaces dtf_model)
