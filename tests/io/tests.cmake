# SPDX-License-Identifier: GPL-3.0-or-later
# Tests of io/ itself (dtf_test(...) lines; the label follows from each file's suffix). The sub-layers have
# their own lists: io/model, io/formats, io/diffusion, io/bids.
dtf_test(test_io SOURCES io/io_phantom_test.cpp LIBS dtf_io)
dtf_test(test_input SOURCES io/input_test.cpp LIBS dtf_io)
