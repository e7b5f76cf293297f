# toolchain-arm-none-eabi.cmake - bare-metal Cortex-M cross build with the
# Debian/Arm GNU toolchain (gcc-arm-none-eabi + libnewlib-arm-none-eabi).
#
# MC_ARM_CPU selects the core (set by the presets in CMakePresets.json):
#   cortex-m4f  Cortex-M4 with FPv4-SP, hard-float ABI   (float build)
#   cortex-m3   Cortex-M3, no FPU, soft-float ABI        (fixed-point build)
#
# Flags shared by every target: -ffunction-sections/-fdata-sections and
# --gc-sections (sizes reported are what is used), -fstack-usage plus
# -fcallgraph-info=su (worst stack depth, tools/bench/stack_depth.py),
# -ffp-contract=off (no fused multiply-add: float results stay bit-identical
# to the x86-64 host build), -fno-math-errno (sqrtf is one vsqrt.f32),
# -fno-short-enums (struct layouts equal the host's, so a host-built config
# blob can be loaded on the target; newlib never sees our enums).
# Link-time optimisation of the qemu images is the option MC_LTO
# (CMakeLists.txt; presets cortex-m4f and cortex-m3-fixed), not a flag here.
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR arm)
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)

set(MC_ARM_CPU "cortex-m4f" CACHE STRING "Target core: cortex-m4f or cortex-m3")
set_property(CACHE MC_ARM_CPU PROPERTY STRINGS cortex-m4f cortex-m3)

set(CMAKE_C_COMPILER arm-none-eabi-gcc)
set(CMAKE_CXX_COMPILER arm-none-eabi-g++)
set(CMAKE_ASM_COMPILER arm-none-eabi-gcc)
set(CMAKE_AR arm-none-eabi-ar CACHE FILEPATH "")
set(CMAKE_RANLIB arm-none-eabi-ranlib CACHE FILEPATH "")
set(CMAKE_OBJDUMP arm-none-eabi-objdump CACHE FILEPATH "")
set(CMAKE_SIZE arm-none-eabi-size CACHE FILEPATH "")

if(MC_ARM_CPU STREQUAL "cortex-m4f")
  set(MC_ARM_FLAGS "-mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16")
  set(MC_QEMU_MACHINE "mps2-an386" CACHE INTERNAL "")
elseif(MC_ARM_CPU STREQUAL "cortex-m3")
  set(MC_ARM_FLAGS "-mcpu=cortex-m3 -mthumb -mfloat-abi=soft")
  set(MC_QEMU_MACHINE "mps2-an385" CACHE INTERNAL "")
else()
  message(FATAL_ERROR "MC_ARM_CPU must be cortex-m4f or cortex-m3, not '${MC_ARM_CPU}'")
endif()

set(MC_ARM_COMMON "-ffunction-sections -fdata-sections -fno-common -ffp-contract=off -fno-math-errno -fno-short-enums -fstack-usage -fcallgraph-info=su")
set(CMAKE_C_FLAGS_INIT "${MC_ARM_FLAGS} ${MC_ARM_COMMON}")
set(CMAKE_CXX_FLAGS_INIT "${MC_ARM_FLAGS} ${MC_ARM_COMMON}")
set(CMAKE_ASM_FLAGS_INIT "${MC_ARM_FLAGS}")
set(CMAKE_EXE_LINKER_FLAGS_INIT "${MC_ARM_FLAGS} -nostartfiles --specs=nano.specs --specs=nosys.specs -Wl,--gc-sections -Wl,--no-enum-size-warning")

set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
