/*
 * align.h - rotor alignment before an open-loop start (not in paper 000).
 *
 * Why: paper 000's open-loop start (68) assumes the rotor rests on the
 * equilibrium of the reference's electrical angle n_p theta_r(0). A stepper
 * at power-up rests on any of its n_p equilibria, or anywhere between them
 * if it was turned by hand; started from a quarter tooth pitch away the
 * open loop drives it against its field and it trips on over-current.
 *
 * How: a current vector is applied in the (f-g) frame of theta_r(0)
 * (voltage R I along the vector, as (68) at rest), in five stages:
 *   1. ramp the magnitude up at angle 0 and hold: the rotor falls into the
 *      equilibrium of electrical angle 0 nearest to it (any start within
 *      half a tooth pitch of it; torque K I sin(n_p dtheta), paper 000 eq. (1));
 *   2. turn the vector to +phi_turn (pi/2) and back to 0 at a constant
 *      rate: a rotor that stage 1 left on the unstable point (exactly half
 *      a pitch away, where the torque is zero) is pulled off it and ends on
 *      the stable one; a rotor already aligned follows and comes back;
 *   3. hold at 0 while the swing of stage 2 settles;
 *   4. ramp the magnitude down, then 0 V until the current has decayed, so
 *      the start that follows (and its R, L measurement) begins from rest
 *      and zero current.
 * The equilibrium found is the nearest one to where the rotor was (a rotor
 * exactly half a pitch away has two, and takes the one ahead); the drive
 * calls it theta_r(0): absolute position is relative to it, as on any
 * sensorless stepper drive.
 * The voltage never steps: it ramps up and down over ramp_ticks.
 */
#ifndef STARTUP_ALIGN_H
#define STARTUP_ALIGN_H

#include <stdbool.h>
#include <stdint.h>

#include "math/frame_fg.h"
#include "math/mc_num.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    int32_t ramp_ticks;    /* magnitude ramp up (stage 1) and down (stage 4); >= 1 */
    int32_t hold_ticks;    /* stage 1 hold at angle 0 */
    int32_t turn_ticks;    /* stage 2, each way (0 -> phi_turn, phi_turn -> 0) */
    int32_t settle_ticks;  /* stage 3 */
    int32_t off_ticks;     /* stage 4 at 0 V after the ramp down */
    mc_t phi_turn_rad;     /* electrical angle of stage 2's excursion */
    bool enabled;          /* false: no alignment (the start assumes the rotor at theta_r(0)) */
} align_config_t;

typedef struct {
    align_config_t cfg;
    int32_t k;             /* samples done */
} align_t;

void align_init(align_t *a, const align_config_t *cfg);

/* Samples from the first to the last of the alignment (0 when disabled). */
int32_t align_total_ticks(const align_config_t *cfg);

/* One sample: the (f-g) voltage [V] of the current vector for a voltage
 * magnitude v_hold_V (R I of the start, (68) at rest). Returns true once
 * the alignment is over (outputs 0 V from then on). */
bool align_step(align_t *a, mc_t v_hold_V, mc_t *v_f_V, mc_t *v_g_V);

#ifdef __cplusplus
}
#endif

#endif /* STARTUP_ALIGN_H */
