# What paper 001's drive needs of a board (checked at configure time by
# hal/backends/stm32f405/CMakeLists.txt against boards/<board>.cmake):
# its configuration's phase count, 3 (a PMSM) or 2 (the stepper)
# (paper001_drive.c: phase_adapter_accepts(in, c->n_phases)); sensorless:
# no angle sensor.
set(MC_DRIVE_PHASES 3 2)
set(MC_DRIVE_ANGLE_SENSOR "")
set(MC_DRIVE_VARIANTS "")
