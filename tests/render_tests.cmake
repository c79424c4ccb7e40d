# Tests of the render area (dtf_test(...) lines).
dtf_test(test_render_passes SOURCES gl/fabric_passes_test.cpp LIBS dtf_render dtf_model)
dtf_test(test_render_unit SOURCES unit/camera_noise_test.cpp LIBS dtf_render dtf_model)
dtf_test(test_render_fabric SOURCES gl/fabric_render_test.cpp LIBS dtf_render dtf_model)
dtf_test(test_render_baseline SOURCES gl/baseline_test.cpp LIBS dtf_render dtf_surfaces dtf_io dtf_model)
dtf_test(test_render_cli SOURCES gl/render_cli_test.cpp LIBS dtf_render dtf_io dtf_model)
dtf_test(test_bench_render_peer SOURCES unit/bench_render_peer_test.cpp LIBS dtf_cli)
dtf_test(test_bench_render_cli SOURCES gl/bench_render_cli_test.cpp LIBS dtf_render dtf_model)
dtf_test(test_gl_state SOURCES gl/gl_state_test.cpp LIBS dtf_render dtf_model)
