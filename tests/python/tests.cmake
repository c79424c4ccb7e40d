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
  # `cmake --install` of the module (component python) into a scratch prefix, then a render from there
  # with nothing of the build tree on the path.
  set(_prefix ${CMAKE_BINARY_DIR}/test_scratch/python_install)
  add_test(NAME python_install COMMAND sh -c
    "rm -rf '${_prefix}' && '${CMAKE_COMMAND}' --install '${CMAKE_BINARY_DIR}' --prefix '${_prefix}' --component python >/dev/null && cd / && PYTHONPATH='${_prefix}/${DTF_PYTHON_INSTALL_DIR}' '${DTF_PYTHON_EXECUTABLE}' -c \"import dtfabric, numpy; assert dtfabric.__file__.startswith('${_prefix}/'), dtfabric.__file__; f = dtfabric.TensorField(numpy.tile(numpy.array([2e-3, 0, 0, 5e-4, 0, 5e-4], numpy.float32), (8, 8, 8, 1)), numpy.eye(4), layout='world'); img = dtfabric.render(f, size=(64, 64)); assert img.shape == (64, 64, 4) and img[..., :3].max() > 0; print('installed', dtfabric.__file__)\"")
  set_tests_properties(python_install PROPERTIES LABELS python)
else()
  add_test(NAME python_module COMMAND sh -c
    "echo 'the Python module was not built (pybind11-dev missing or DTF_PYTHON=OFF)' >&2; case \"$DTF_REQUIRE_TOOLS\" in ''|0) exit 77;; *) exit 1;; esac")
  set_tests_properties(python_module PROPERTIES LABELS python SKIP_RETURN_CODE 77)
endif()
