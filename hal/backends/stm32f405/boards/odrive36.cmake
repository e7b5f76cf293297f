# What the ODrive v3.6 offers a drive (boards/odrive36.c is its table; its
# _Static_assert holds the two equal): read at configure time by
# ../CMakeLists.txt, which refuses a drive whose needs
# (firmware/drives/<drive>/needs.cmake) the board does not meet.
# Sources: the ODrive v3.6 schematic and the ODrive firmware's hardware
# configuration Firmware/Board/v3/Inc/main.h, board.cpp, Src/adc.c
# (github.com/odriverobotics/ODrive).
set(MC_BOARD_TITLE "ODrive v3.6 (STM32F405RG, two DRV8301)")
# two axes of three legs each (M0 on TIM1, M1 on TIM8), shunts on legs B
# and C of each (main.h M0_IB, M0_IC, M1_IB, M1_IC): the image drives legs
# B and C of both, a full bridge per winding, a 2-phase stepper; one
# 3-phase motor on this backend would need an axis's three legs and the
# third current (the board measures two of each axis): not offered here
set(MC_BOARD_PHASES 2)
set(MC_BOARD_POWER_STAGE "two full bridges (legs B and C of its axes M0 and M1: one 2-phase stepper)")
# the encoder ports (TIM3, TIM4) are not wired into this backend's table
set(MC_BOARD_ANGLE_SENSORS "")
