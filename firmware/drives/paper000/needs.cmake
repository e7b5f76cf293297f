# What paper 000's drive needs of a board (checked at configure time by
# hal/backends/stm32f405/CMakeLists.txt against boards/<board>.cmake):
# a 2-phase hybrid stepper, each winding across its own full bridge, both
# winding currents (paper000_drive.c: phase_adapter_accepts(in, P000_N_PHASES));
# sensorless: no angle sensor.
set(MC_DRIVE_PHASES 2)
set(MC_DRIVE_ANGLE_SENSOR "")
set(MC_DRIVE_VARIANTS "")
