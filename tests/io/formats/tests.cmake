# SPDX-License-Identifier: GPL-3.0-or-later
# Tests of io/formats/ (dtf_test(...) lines; the label follows from each file's suffix).
dtf_test(test_io_nifti SOURCES io/formats/io_nifti_test.cpp LIBS dtf_io dtf_nifti)
dtf_test(test_io_formats SOURCES io/formats/io_formats_test.cpp LIBS dtf_io dtf_model ZLIB::ZLIB)
dtf_test(test_fibres SOURCES io/formats/fibre_io_test.cpp LIBS dtf_io)
dtf_test(test_function_length SOURCES io/formats/function_length_test.cpp LIBS dtf_model)
dtf_test(test_gzip_io SOURCES io/formats/gzip_io_test.cpp LIBS dtf_io dtf_model ZLIB::ZLIB)
dtf_test(test_peaks_detection SOURCES io/formats/peaks_detection_test.cpp LIBS dtf_io dtf_model)
dtf_test(test_process SOURCES io/formats/process_test.cpp LIBS dtf_io dtf_model)
