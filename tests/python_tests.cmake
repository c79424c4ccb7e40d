# The Python module's pytest suite (tests/python), run by the interpreter the module was built for, with the
# build tree's package on PYTHONPATH and the built command-line tool to compare with. Without the module
# (no pybind11) the test fails under DTF_REQUIRE_TOOLS=1 and is skipped otherwise.
if(DTF_PYTHON_MODULE)
  add_test(NAME python_module COMMAND ${DTF_PYTHON_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/python/run_pytest.py)
  set_tests_properties(python_module PROPERTIES
    LABELS python
    SKIP_RETURN_CODE 77
    TIMEOUT 600
    ENVIRONMENT "PYTHONPATH=${CMAKE_BINARY_DIR}/app/python;DTF_EXE=$<TARGET_FILE:dtfabric>;DTF_SOURCE_DIR=${CMAKE_SOURCE_DIR}")
else()
  add_test(NAME python_module COMMAND sh -c
    "echo 'the Python module was not built (pybind11-dev missing or DTF_PYTHON=OFF)' >&2; case \"$DTF_REQUIRE_TOOLS\" in ''|0) exit 77;; *) exit 1;; esac")
  set_tests_properties(python_module PROPERTIES LABELS python SKIP_RETURN_CODE 77)
endif()
