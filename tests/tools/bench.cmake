# Python tests of scripts/, .ci/run, README.md and tools/bench/ (owned with
# them). Included from tests/tools/CMakeLists.txt; MC_PYTHON is the venv's
# python (tests/CMakeLists.txt). -p no:cacheprovider: no .pytest_cache in the
# source tree.
add_test(NAME tools.bench_realtime
  COMMAND ${MC_PYTHON} -m pytest -q -p no:cacheprovider ${CMAKE_CURRENT_LIST_DIR}/test_bench_realtime.py
  WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
add_test(NAME tools.scripts
  COMMAND ${MC_PYTHON} -m pytest -q -p no:cacheprovider ${CMAKE_CURRENT_LIST_DIR}/test_scripts.py
  WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
set_tests_properties(tools.bench_realtime tools.scripts PROPERTIES TIMEOUT 300 LABELS "tools;python")
