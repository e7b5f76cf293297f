# What the sensored FOC drive needs of a board (checked at configure time by
# hal/backends/stm32f405/CMakeLists.txt against boards/<board>.cmake):
# a 3-phase PMSM and an encoder (sensored_foc_drive.c: phase_adapter_accepts(in,
# SFOC_N_PHASES) and has_angle, else BAD_INPUT).
set(MC_DRIVE_PHASES 3)
set(MC_DRIVE_ANGLE_SENSOR encoder)
set(MC_DRIVE_VARIANTS "")
