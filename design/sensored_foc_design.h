/*
 * sensored_foc_design.h - the sensored FOC drive's configuration
 * (drives/sensored_foc/sensored_foc_drive.h) from the motor, the bounds
 * and three bandwidths, in double, folded once into the firmware type.
 *
 * Current loops (PI with the decoupling terms fed forward): the plant
 * seen by each is 1/(R + L s); with kp = L w_c and ki = R w_c the PI's
 * zero cancels the pole and the loop is w_c / s (Harnefors, "Control of
 * variable-speed drives", 2002, sec. 3.2; ODrive and MESC set their
 * current gains this way). The computation delay (1/2 + d) Ts, plus the
 * half sample of the zero-order hold, costs w_c (1 + d) Ts of phase
 * margin: 0.63 rad (36 deg) at the default w_c = 2 pi 500 Hz, d = 1 and
 * 10 kHz, leaving 54 deg.
 * Speed loop (PI, the load and J a_ref fed forward): the plant is
 * K_t / (J s); kp = J w_s / K_t puts the crossover at w_s, ki = kp w_s / 4
 * the PI's zero a quarter below it (about 60 deg of margin).
 * Encoder observer (estimators/encoder_observer.h): two poles at -w_o
 * (angle and speed) and one at -w_L (the load): the characteristic
 * polynomial s^3 + l1 s^2 + l2 s + l3/J = (s + w_o)^2 (s + w_L) gives
 * l1 = 2 w_o + w_L, l2 = w_o^2 + 2 w_o w_L, l3 = J w_o^2 w_L. The load's
 * pole is slower: l3 carries the encoder's quantisation and noise into the
 * load estimate (and, fed forward, into the torque) in proportion to it.
 * Position loop (moves): kp = w_p [1/s], below the speed loop.
 * Defaults: 500 Hz current, 20 Hz speed, 50 Hz observer, 5 Hz load, 5 Hz
 * position (the observer 2.5 times faster than the speed loop it feeds;
 * the load estimate, fed forward, slower than the speed loop, whose
 * integral takes the load's fast part).
 */
#ifndef DESIGN_SENSORED_FOC_DESIGN_H
#define DESIGN_SENSORED_FOC_DESIGN_H

#include <stdbool.h>
#include <stddef.h>

#include "design/motor_design.h"
#include "drives/sensored_foc/sensored_foc_drive.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    /* the one motor design input (design/motor_design.h): n_p, R_ohm,
     * L_d = L_H, L_q_H, psi = K_Nm_per_A / n_p, J_kgm2; friction is left to
     * the speed loop's integral and the load estimate */
    motor_design_input_t motor;
    double ts_s;
    double compute_delay_samples;   /* [0, 1] */
    double v_bus_V;                 /* the nominal bus: CmdSpeed's bound */
    double i_max_A, i_trip_A;
    int i_trip_samples;             /* 0 or 1: instantaneous, up to 8 */
    double i_rail_A;                /* 0: unknown */
    double current_bw_hz, speed_bw_hz, observer_bw_hz, load_bw_hz, position_bw_hz;
    size_t n_points;                /* speed profile corners */
    double t_s[SPEED_PROFILE_MAX_POINTS];
    double omega_rad_s[SPEED_PROFILE_MAX_POINTS];
} sfoc_design_input_t;

/* The defaults: bandwidths 500 / 20 / 50 / 5 / 5 Hz, no delay, a profile at rest. */
void sfoc_design_defaults(sfoc_design_input_t *in);

/* Validates *in and derives *cfg. False with the first problem (naming the
 * field and the value) in err. */
bool sfoc_design(const sfoc_design_input_t *in, sensored_foc_config_t *cfg, char *err, size_t err_len);

#ifdef __cplusplus
}
#endif

#endif /* DESIGN_SENSORED_FOC_DESIGN_H */
