# Regenerates every drive's parameter values for an STM32F405 board from
# the scenario beside it (firmware/drives/<drive>/boards/<board>.toml ->
# <board>_params.c, mc_pil_gen --board-params --drive <drive>, run from the
# repository's root so the recorded path is the same) and compares them
# with the committed file; the generator also refuses a scenario whose
# design the values do not reproduce bit for bit.
# -DGEN=mc_pil_gen -DSRC=<repository> -DWORK=<scratch folder>
file(MAKE_DIRECTORY ${WORK})
file(GLOB scenarios RELATIVE ${SRC} ${SRC}/firmware/drives/*/boards/*.toml)
if(NOT scenarios)
  message(FATAL_ERROR "no board scenario found (firmware/drives/*/boards/*.toml)")
endif()
foreach(toml ${scenarios})
  string(REGEX MATCH "firmware/drives/([^/]+)/boards/([^/]+)\\.toml$" _m ${toml})
  set(drive ${CMAKE_MATCH_1})
  set(board ${CMAKE_MATCH_2})
  set(committed ${SRC}/firmware/drives/${drive}/boards/${board}_params.c)
  set(fresh ${WORK}/${drive}_${board}_params.c)
  execute_process(COMMAND ${GEN} --board-params --drive ${drive} ${toml} ${fresh}
                  WORKING_DIRECTORY ${SRC} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "mc_pil_gen --board-params failed for ${drive} on ${board} (${rc})")
  endif()
  if(NOT EXISTS ${committed})
    message(FATAL_ERROR "${committed} missing: generate it from ${toml} (hal/backends/stm32f405/README.md)")
  endif()
  file(READ ${committed} a)
  file(READ ${fresh} b)
  if(NOT a STREQUAL b)
    message(FATAL_ERROR "${committed} is not what mc_pil_gen --board-params gives now from ${toml}: "
                        "regenerate it (hal/backends/stm32f405/README.md)")
  endif()
  message(STATUS "${drive} on ${board}: parameter values current")
endforeach()
