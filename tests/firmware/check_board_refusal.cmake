# A (drive, board) pair the board cannot run is refused when the STM32F405
# image is configured, with a message that says why
# (hal/backends/stm32f405/CMakeLists.txt: the drive's needs.cmake against the
# board's <board>.cmake): configures each pair below in a scratch folder and
# expects the configuration to fail with the given words.
# -DSRC=<repository> -DWORK=<scratch folder>
cmake_minimum_required(VERSION 3.25)
find_program(_gcc arm-none-eabi-gcc)
if(NOT _gcc)
  message(STATUS "no arm-none-eabi-gcc: skipped")
  return()
endif()
# drive|board|variant|words the refusal must contain
set(cases
  "paper000|vesc6||MC_DRIVE=paper000 cannot run on MC_BOARD=vesc6: the drive needs 2 phase(s)"
  "paper002|odrive36|sensorless|MC_DRIVE=paper002 cannot run on MC_BOARD=odrive36: the drive needs 3 phase(s)"
  "paper001|vesc6|sensorless|not a variant of the drive paper001"
  "paper001|nosuchboard||MC_BOARD='nosuchboard': not a board")
set(failed "")
foreach(c ${cases})
  string(REPLACE "|" ";" f "${c}")
  list(GET f 0 drive)
  list(GET f 1 board)
  list(GET f 2 variant)
  list(GET f 3 words)
  file(REMOVE_RECURSE ${WORK}/${drive}_${board})
  execute_process(COMMAND ${CMAKE_COMMAND} --preset stm32f405 -S ${SRC} -B ${WORK}/${drive}_${board}
                          -DMC_DRIVE=${drive} -DMC_BOARD=${board} -DMC_DRIVE_VARIANT=${variant}
                  WORKING_DIRECTORY ${SRC} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  string(REGEX REPLACE "[ \n]+" " " flat "${out} ${err}")
  string(FIND "${flat}" "${words}" at)
  if(rc EQUAL 0 OR at EQUAL -1)
    list(APPEND failed "${drive} on ${board} ${variant}: rc ${rc}, expected a refusal with '${words}', got: ${flat}")
  else()
    message(STATUS "${drive} on ${board} ${variant}: refused (${words})")
  endif()
endforeach()
if(failed)
  message(FATAL_ERROR "${failed}")
endif()
