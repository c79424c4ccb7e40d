# SPDX-License-Identifier: GPL-3.0-or-later
# Tests of surfaces/selection/ (ROI selection of streamlines): the semantics on lines with known answers, and
# the index against the walk on random tractograms.
dtf_test(test_tract_selection SOURCES surfaces/selection/tract_selection_test.cpp LIBS dtf_surfaces dtf_model)
