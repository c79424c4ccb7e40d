# SPDX-License-Identifier: GPL-3.0-or-later
# The Python module's pytest suite (tests/python), run by the interpreter the module was built for, with the
# build tree's package on PYTHONPATH and the built command-line tool to compare with. Without the module
# (no pybind11) the test fails under DTF_REQUIRE_TOOLS=1 and is skipped otherwise.
if(DTF_PYTHON_MODULE)
  # Under DTF_SANITIZE the extension is instrumented but the interpreter is not: the ASan runtime must be
  # loaded first, and libstdc++ with it (else ASan's __cxa_throw interceptor finds no real function and
  # aborts on the first C++ exception). .ci/sanitize runs these with leak checking off (the interpreter's own
  # allocations live until exit).
  set(_python_env "PYTHONPATH=${CMAKE_BINARY_DIR}/app/python;DTF_EXE=$<TARGET_FILE:dtfabric>;DTF_SOURCE_DIR=${CMAKE_SOURCE_DIR}")
  set(_preload "")
  if(DTF_SANITIZE)
    execute_process(COMMAND ${CMAKE_CXX_COMPILER} -print-file-name=libasan.so OUTPUT_VARIABLE _asan
                    OUTPUT_STRIP_TRAILING_WHITESPACE)
    execute_process(COMMAND ${CMAKE_CXX_COMPILER} -print-file-name=libstdc++.so.6 OUTPUT_VARIABLE _stdcxx
                    OUTPUT_STRIP_TRAILING_WHITESPACE)
    set(_preload "LD_PRELOAD=${_asan} ${_stdcxx}")
    list(APPEND _python_env "${_preload}")
  endif()
  add_test(NAME python_module COMMAND ${DTF_PYTHON_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/python/run_pytest.py)
  set_tests_properties(python_module PROPERTIES
    LABELS python
    SKIP_RETURN_CODE 77
    TIMEOUT 600
    ENVIRONMENT "${_python_env}")
  # A notebook executed headless (jupyter nbconvert --execute): render() and show() display PNGs, web() an
  # iframe onto its page.
  add_test(NAME python_notebook COMMAND ${DTF_PYTHON_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/python/run_notebook.py)
  set_tests_properties(python_notebook PROPERTIES
    LABELS python
    SKIP_RETURN_CODE 77
    TIMEOUT 600
    ENVIRONMENT "${_python_env};DTF_SCRATCH=${CMAKE_BINARY_DIR}/test_scratch")
  # `cmake --install` of the module (component python) into a scratch prefix, then a render from there
  # with nothing of the build tree on the path.
  set(_prefix ${CMAKE_BINARY_DIR}/test_scratch/python_install)
  add_test(NAME python_install COMMAND sh -c
    "rm -rf '${_prefix}' && '${CMAKE_COMMAND}' --install '${CMAKE_BINARY_DIR}' --prefix '${_prefix}' --component python >/dev/null && cd / && PYTHONPATH='${_prefix}/${DTF_PYTHON_INSTALL_DIR}' '${DTF_PYTHON_EXECUTABLE}' -c \"import dtfabric, numpy; assert dtfabric.__file__.startswith('${_prefix}/'), dtfabric.__file__; f = dtfabric.TensorField(numpy.tile(numpy.array([2e-3, 0, 0, 5e-4, 0, 5e-4], numpy.float32), (8, 8, 8, 1)), numpy.eye(4), layout='world'); img = dtfabric.render(f, size=(64, 64)); assert img.shape == (64, 64, 4) and img[..., :3].max() > 0; print('installed', dtfabric.__file__)\"")
  set_tests_properties(python_install PROPERTIES LABELS python ENVIRONMENT "${_preload}")
else()
  add_test(NAME python_module COMMAND sh -c
    "echo 'the Python module was not built (pybind11-dev missing or DTF_PYTHON=OFF)' >&2; case \"$DTF_REQUIRE_TOOLS\" in ''|0) exit 77;; *) exit 1;; esac")
  set_tests_properties(python_module PROPERTIES LABELS python SKIP_RETURN_CODE 77)
endif()
