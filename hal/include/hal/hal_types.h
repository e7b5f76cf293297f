/*
 * hal_types.h - the data that crosses the hardware interface once per PWM
 * period: one sample in (phase currents, bus voltage, optional position
 * sensor, backend status) and one command out (phase voltages). Data only,
 * no functions, so the control code (firmware/) can read and write it
 * without depending on any backend.
 *
 * The same two structs serve a two-phase stepper (two H-bridges: phases a,
 * b) and a three-phase PMSM (three half-bridges: phases a, b, c); the count
 * is a field, not a second header. The interface grows like NuttX's FOC
 * lower half: a new measurement is a new field with a flag or a status bit
 * saying whether the backend provides it; existing backends, which zero the
 * structs before filling them, keep working unchanged.
 * All values are SI (A, V, rad) in the firmware numeric type mc_t: the
 * type alone (math/mc_type.h), none of its operations.
 */
#ifndef HAL_HAL_TYPES_H
#define HAL_HAL_TYPES_H

#include <stdbool.h>
#include <stdint.h>

#include "math/mc_type.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Largest phase count of any supported motor. */
#define HAL_MAX_PHASES 3

/* Bits of hal_sample_t.status: what the backend noticed this period. */
#define HAL_STATUS_OVERRUN      (1u << 0) /* the previous control call did not finish within its period */
#define HAL_STATUS_ADC_FAULT    (1u << 1) /* converter error or timeout: the currents are not trustworthy */
#define HAL_STATUS_PWM_TRIP     (1u << 2) /* hardware over-current / break input fired: outputs are off */
#define HAL_STATUS_BUS_INVALID  (1u << 3) /* no bus voltage measurement this period (v_bus_V not valid) */

/* One period's measurements, taken at the sampling instant (start of the
 * period for the software plant, PWM centre on an MCU). */
typedef struct {
    uint32_t tick;               /* period counter since hal_start */
    uint8_t n_phases;            /* 2 (phases a, b) or 3 (a, b, c) */
    mc_t i_A[HAL_MAX_PHASES];    /* phase currents; the unused entry is 0 */
    mc_t v_bus_V;                /* DC bus voltage (see HAL_STATUS_BUS_INVALID) */
    bool has_angle;              /* a position sensor is fitted and read this period */
    mc_t angle_rad;              /* its mechanical angle, valid when has_angle */
    uint32_t status;             /* HAL_STATUS_* bits */
} hal_sample_t;

/* Phase voltages to hold over the next period. Two phases: the voltage
 * across each winding (an H-bridge each). Three phases: each leg's voltage
 * with respect to the bus midpoint, so |v| <= v_bus/2 per leg. */
typedef struct {
    uint8_t n_phases;            /* as in the sample */
    mc_t v_V[HAL_MAX_PHASES];
} hal_command_t;

/* One classic CAN frame (11-bit identifier), for hal_can_send/receive and
 * the firmware's CAN link (comm/can_link.h). */
typedef struct {
    uint32_t id;                 /* standard identifier, 0-0x7FF */
    uint8_t dlc;                 /* data length, 0-8 */
    uint8_t data[8];
} hal_can_frame_t;

#ifdef __cplusplus
}
#endif

#endif /* HAL_HAL_TYPES_H */
