# SPDX-License-Identifier: GPL-3.0-or-later
# Tests of surfaces/analyses/ (dtf_test(...) lines; the label follows from each file's suffix).
dtf_test(test_orientation_check SOURCES surfaces/analyses/orientation_check_test.cpp LIBS dtf_surfaces dtf_io dtf_model)
dtf_test(test_fibre_orientation_check SOURCES surfaces/analyses/fibre_orientation_check_test.cpp LIBS dtf_surfaces dtf_io dtf_model)
dtf_test(test_fibre_agreement SOURCES surfaces/analyses/fibre_agreement_test.cpp LIBS dtf_surfaces dtf_io dtf_model)
dtf_test(test_tract_agreement SOURCES surfaces/analyses/tract_agreement_test.cpp LIBS dtf_surfaces dtf_io dtf_model)
dtf_test(test_tract_profile SOURCES surfaces/analyses/tract_profile_test.cpp surfaces/analyses/tract_proximity_test.cpp LIBS dtf_surfaces dtf_model)
