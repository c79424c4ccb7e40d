# Tractograms from every tool: TRX, TrackVis (plain and gzip) with nibabel's rules, MRtrix, VTK; `info` and
# `convert` on tract files.
dtf_test(test_tract_formats SOURCES unit/tract_formats_test.cpp LIBS dtf_scene dtf_surfaces dtf_io dtf_model ZLIB::ZLIB)
dtf_test(test_tract_convert_cli SOURCES cli/tract_convert_cli_test.cpp LIBS dtf_model)
dtf_test(test_tract_colour_cli SOURCES gl/tract_colour_cli_test.cpp LIBS dtf_render dtf_io dtf_model)
