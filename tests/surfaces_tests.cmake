# Tests of the surfaces area.
dtf_test(test_surfaces LABEL unit SOURCES unit/surfaces_test.cpp LIBS dtf_surfaces dtf_model)
