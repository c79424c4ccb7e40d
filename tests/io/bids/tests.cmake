# SPDX-License-Identifier: GPL-3.0-or-later
# Tests of io/bids/ (dtf_test(...) lines; the label follows from each file's suffix).
dtf_test(test_bids SOURCES io/bids/bids_test.cpp LIBS dtf_io dtf_model nlohmann_json::nlohmann_json)
