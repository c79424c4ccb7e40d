# Tests of io/ (dtf_test(...) lines; the label follows from each file's suffix).
dtf_test(test_bids SOURCES io/bids_test.cpp LIBS dtf_io dtf_model)
dtf_test(test_fibres SOURCES io/fibre_io_test.cpp LIBS dtf_io)
dtf_test(test_fit_gradients SOURCES io/fit_gradients_test.cpp LIBS dtf_io)
dtf_test(test_fit_tensor SOURCES io/fit_tensor_test.cpp LIBS dtf_io)
dtf_test(test_fit_real_data SOURCES io/fit_real_data_test.cpp LIBS dtf_io)
dtf_test(test_io SOURCES io/io_nifti_test.cpp io/io_phantom_test.cpp LIBS dtf_io dtf_nifti)
dtf_test(test_io_formats SOURCES io/io_formats_test.cpp LIBS dtf_io dtf_model ZLIB::ZLIB)
