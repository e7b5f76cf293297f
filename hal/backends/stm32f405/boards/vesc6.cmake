# What the VESC 6 offers a drive (boards/vesc6.c is its table; its
# _Static_asserts hold the two equal): read at configure time by
# ../CMakeLists.txt, which refuses a drive whose needs
# (firmware/drives/<drive>/needs.cmake) the board does not meet.
# Sources: the VESC 6 schematic (github.com/vedderb/bldc-hardware) and the
# VESC firmware's hardware configuration hwconf/hw_60.h (github.com/vedderb/bldc).
set(MC_BOARD_TITLE "VESC 6 (STM32F405RG, DRV8301)")
# three half-bridges (TIM1 CH1-3/CH1N-3N) with a shunt on each low side
# (hw_60.h: HW_HAS_3_SHUNTS, HW_HAS_PHASE_SHUNTS): a 3-phase motor; two
# full bridges (a 2-phase stepper: four legs) it does not have
set(MC_BOARD_PHASES 3)
set(MC_BOARD_POWER_STAGE "three half-bridges (one 3-phase motor; a 2-phase stepper needs two full bridges, four legs)")
# the Hall/encoder port (hw_60.h "Hall/encoder pins": PC6, PC7, PC8 on
# HW_ENC_TIM TIM3): an incremental encoder, A and B on TIM3 CH1/CH2, the
# index on PC8
set(MC_BOARD_ANGLE_SENSORS encoder)
