# Regenerates each STM32F405 board's drive configuration from its scenario
# (mc_pil_gen --board-config, run from the repository's root so the
# recorded path is the same) and compares it with the committed file.
# -DGEN=mc_pil_gen -DSRC=<repository> -DWORK=<scratch folder>
file(MAKE_DIRECTORY ${WORK})
foreach(board vesc6)
  set(committed ${SRC}/hal/backends/stm32f405/boards/${board}_drive_config.c)
  set(fresh ${WORK}/${board}_drive_config.c)
  execute_process(COMMAND ${GEN} --board-config hal/backends/stm32f405/boards/${board}_paper001.toml ${fresh}
                  WORKING_DIRECTORY ${SRC} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "mc_pil_gen --board-config failed for ${board} (${rc})")
  endif()
  file(READ ${committed} a)
  file(READ ${fresh} b)
  if(NOT a STREQUAL b)
    message(FATAL_ERROR "${committed} is not what the host designs now from boards/${board}_paper001.toml: "
                        "regenerate it (hal/backends/stm32f405/README.md)")
  endif()
  message(STATUS "${board}: drive configuration current")
endforeach()
