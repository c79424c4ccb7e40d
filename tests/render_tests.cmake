# Tests of the render area (dtf_test(...) lines).
dtf_test(test_render_passes LABEL gl SOURCES gl/fabric_passes_test.cpp LIBS dtf_render dtf_model)
dtf_test(test_render_unit LABEL unit SOURCES gl/camera_noise_test.cpp LIBS dtf_render dtf_model)
dtf_test(test_render_fabric LABEL gl SOURCES gl/fabric_render_test.cpp LIBS dtf_render dtf_model)
dtf_test(test_render_baseline LABEL baseline SOURCES gl/baseline_test.cpp LIBS dtf_render dtf_surfaces dtf_io dtf_model)
dtf_test(test_render_cli LABEL cli SOURCES gl/render_cli_test.cpp LIBS dtf_render dtf_io dtf_model)
dtf_test(test_bench_render_peer LABEL unit SOURCES unit/bench_render_peer_test.cpp LIBS dtf_cli)
dtf_test(test_bench_render_cli LABEL cli SOURCES gl/bench_render_cli_test.cpp LIBS dtf_render dtf_model)
dtf_test(test_gl_state LABEL gl SOURCES gl/gl_state_test.cpp LIBS dtf_render dtf_model)
