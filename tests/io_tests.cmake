# Tests of the io area (dtf_test(...) lines). test_io links nifticlib itself to craft files of other
# datatypes; malformed files are made by the tests from valid ones, never committed.
dtf_test(test_io SOURCES unit/io_nifti_test.cpp unit/io_phantom_test.cpp LIBS dtf_io dtf_nifti)
dtf_test(test_io_cli SOURCES cli/io_cli_test.cpp LIBS dtf_io)
# Other tools' formats (MRtrix, FSL dtifit sets, NRRD, DSI Studio): files written by the tests, real files read.
dtf_test(test_io_formats SOURCES unit/io_formats_test.cpp LIBS dtf_io dtf_model ZLIB::ZLIB)
dtf_test(test_formats_cli SOURCES cli/formats_cli_test.cpp LIBS dtf_io dtf_model)
