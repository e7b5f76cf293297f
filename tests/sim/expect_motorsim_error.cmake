# cmake -P script: runs motorsim with arguments that must be rejected and
# checks the contract of a rejection:
#   - non-zero exit status,
#   - exactly one line on stderr, starting with "error: " and containing
#     every EXPECT substring (file and key),
#   - nothing on stdout,
#   - no output file or directory created (motorsim runs in WORK, so a
#     default ./out would be seen too).
# Variables: MOTORSIM (binary), WORK (scratch dir, wiped), ARGS (motorsim
# arguments separated by '|'), EXPECT (substrings separated by '|'), MODE
# (the output arguments added to ARGS: "full", the default: --out and
# --metrics-out; "metrics_only": --metrics-out alone; "none": nothing).
foreach(v MOTORSIM WORK ARGS)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "expect_motorsim_error.cmake: ${v} not set")
  endif()
endforeach()

file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}")
string(REPLACE "|" ";" arg_list "${ARGS}")
# Outputs would go to a directory that does not exist yet and to a metrics
# path below another missing one: neither may appear.
if(NOT DEFINED MODE OR MODE STREQUAL "" OR MODE STREQUAL "full")
  set(out_args --out "${WORK}/out" --metrics-out "${WORK}/m/metrics.json" --no-plot)
elseif(MODE STREQUAL "metrics_only")
  set(out_args --metrics-out "${WORK}/m/metrics.json")
elseif(MODE STREQUAL "none")
  set(out_args "")
else()
  message(FATAL_ERROR "expect_motorsim_error.cmake: unknown MODE '${MODE}'")
endif()
execute_process(
  COMMAND "${MOTORSIM}" ${arg_list} ${out_args}
  WORKING_DIRECTORY "${WORK}"
  RESULT_VARIABLE rc
  OUTPUT_VARIABLE out
  ERROR_VARIABLE err)

set(fail "")
if(rc EQUAL 0)
  string(APPEND fail "\n  exit status 0, expected non-zero")
endif()
string(REGEX REPLACE "\n$" "" err_line "${err}")
if(err_line MATCHES "\n")
  string(APPEND fail "\n  stderr has more than one line")
endif()
if(NOT err_line MATCHES "^error: ")
  string(APPEND fail "\n  stderr does not start with 'error: '")
endif()
if(DEFINED EXPECT AND NOT EXPECT STREQUAL "")
  string(REPLACE "|" ";" expect_list "${EXPECT}")
  foreach(e IN LISTS expect_list)
    string(FIND "${err_line}" "${e}" pos)
    if(pos EQUAL -1)
      string(APPEND fail "\n  stderr lacks '${e}'")
    endif()
  endforeach()
endif()
if(NOT out STREQUAL "")
  string(APPEND fail "\n  unexpected stdout: ${out}")
endif()
file(GLOB left LIST_DIRECTORIES true "${WORK}/*" "${WORK}/.*")
if(left)
  string(APPEND fail "\n  output written: ${left}")
endif()

if(fail)
  message(FATAL_ERROR "motorsim ${arg_list}: rc=${rc}${fail}\n  stderr was: ${err}")
endif()
message(STATUS "ok: rc=${rc}: ${err_line}")
file(REMOVE_RECURSE "${WORK}")
