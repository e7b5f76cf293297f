# What paper 002's drive needs of a board (checked at configure time by
# hal/backends/stm32f405/CMakeLists.txt against boards/<board>.cmake):
# a 3-phase IPMSM (paper002_drive.c: phase_adapter_accepts(in, 3u)) and the
# rotor's angle from an encoder (cfg.angle_source P002_ANGLE_ENCODER: a
# sample without has_angle is BAD_INPUT). The variant "sensorless"
# (MC_DRIVE_VARIANT; its configuration <board>_sensorless.toml sets
# estimator = "flux", P002_ANGLE_FLUX) reads no sensor.
set(MC_DRIVE_PHASES 3)
set(MC_DRIVE_ANGLE_SENSOR encoder)
set(MC_DRIVE_VARIANTS sensorless)
if(MC_DRIVE_VARIANT STREQUAL "sensorless")
  set(MC_DRIVE_ANGLE_SENSOR "")
endif()
