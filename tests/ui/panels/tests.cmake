# SPDX-License-Identifier: GPL-3.0-or-later
# Tests of ui/panels/ (dtf_test(...) lines; the label follows from each file's suffix).
dtf_test(test_view_ui SOURCES ui/panels/view_ui_test.cpp LIBS dtf_ui)
dtf_test(test_orientation_banner SOURCES ui/panels/orientation_banner_test.cpp LIBS dtf_ui)
