# cmake -P script: runs motorsim on a run that must FAIL and checks the
# contract of a failed run (issue 9):
#   - the exit status is STATUS (3 fault, 4 [expect] missed, 5 diverged),
#   - stderr contains every EXPECT substring (what happened, when, the value),
#   - the outputs are complete anyway: DIR/<stem>.csv with a header and at
#     least one row, and the metrics JSON with its "fault" key.
# Variables: MOTORSIM, WORK (scratch, wiped), SCENARIO, STEM, STATUS,
# EXPECT (substrings separated by '|').
foreach(v MOTORSIM WORK SCENARIO STEM STATUS)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "expect_motorsim_status.cmake: ${v} not set")
  endif()
endforeach()
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}")
execute_process(
  COMMAND "${MOTORSIM}" --scenario "${SCENARIO}" --out "${WORK}/out" --no-plot --quiet
  RESULT_VARIABLE rc
  OUTPUT_VARIABLE out
  ERROR_VARIABLE err)
set(fail "")
if(NOT rc EQUAL STATUS)
  string(APPEND fail "\n  exit status ${rc}, expected ${STATUS}")
endif()
if(DEFINED EXPECT AND NOT EXPECT STREQUAL "")
  string(REPLACE "|" ";" expect_list "${EXPECT}")
  foreach(e IN LISTS expect_list)
    string(FIND "${err}" "${e}" pos)
    if(pos EQUAL -1)
      string(APPEND fail "\n  stderr lacks '${e}'")
    endif()
  endforeach()
endif()
set(csv "${WORK}/out/${STEM}.csv")
set(json "${WORK}/out/${STEM}_metrics.json")
if(NOT EXISTS "${csv}")
  string(APPEND fail "\n  no CSV ${csv}")
else()
  file(STRINGS "${csv}" lines LIMIT_COUNT 2)
  list(LENGTH lines n)
  if(n LESS 2)
    string(APPEND fail "\n  CSV has no data row")
  endif()
endif()
if(NOT EXISTS "${json}")
  string(APPEND fail "\n  no metrics JSON ${json}")
else()
  file(READ "${json}" j)
  string(FIND "${j}" "\"fault\"" pos)
  if(pos EQUAL -1)
    string(APPEND fail "\n  metrics JSON without \"fault\"")
  endif()
endif()
if(fail)
  message(FATAL_ERROR "motorsim --scenario ${SCENARIO}: rc=${rc}${fail}\n  stderr was: ${err}")
endif()
message(STATUS "ok: rc=${rc}: ${err}")
file(REMOVE_RECURSE "${WORK}")
