# MC_DRIVE: the drive of the bare-metal images (the PIL image of
# hal/backends/mcu and the STM32F405 image), one configure-time option; a
# name of firmware/drives/registry.c (each `&<name>_drive_ops`). The cross
# presets set it (CMakePresets.json); a name the registry does not hold
# stops the configuration here, with the list of those it does.
set(MC_DRIVE "" CACHE STRING "Drive of the bare-metal images: a name of firmware/drives/registry.c")
file(STRINGS ${PROJECT_SOURCE_DIR}/firmware/drives/registry.c _mc_ops_lines REGEX "&[a-z0-9_]+_drive_ops")
set(MC_DRIVES "")
foreach(_l IN LISTS _mc_ops_lines)
  string(REGEX MATCH "&([a-z0-9_]+)_drive_ops" _m "${_l}")
  list(APPEND MC_DRIVES ${CMAKE_MATCH_1})
endforeach()
set_property(CACHE MC_DRIVE PROPERTY STRINGS ${MC_DRIVES})
if(MC_STRICT_TYPES AND NOT MC_DRIVE)
  # the strict-type build only compiles the images' C: any drive will do
  list(GET MC_DRIVES 0 MC_DRIVE)
endif()
if(NOT MC_DRIVE IN_LIST MC_DRIVES)
  message(FATAL_ERROR "MC_DRIVE='${MC_DRIVE}': the bare-metal images need one drive of the registry "
                      "(firmware/drives/registry.c): ${MC_DRIVES}")
endif()
if(NOT EXISTS ${PROJECT_SOURCE_DIR}/firmware/drives/${MC_DRIVE}/${MC_DRIVE}_drive.h)
  message(FATAL_ERROR "MC_DRIVE='${MC_DRIVE}': firmware/drives/${MC_DRIVE}/${MC_DRIVE}_drive.h not found "
                      "(a drive's folder holds <name>_drive.h with <name>_drive_t and <name>_drive_step)")
endif()
message(STATUS "Drive of the bare-metal images (MC_DRIVE): ${MC_DRIVE}")
