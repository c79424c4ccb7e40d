# SPDX-License-Identifier: GPL-3.0-or-later
# Tests of app/bench/ (dtf_test(...) lines; the label follows from each file's suffix).
dtf_test(test_bench_render_peer SOURCES app/bench/bench_render_peer_test.cpp LIBS dtf_bench)
