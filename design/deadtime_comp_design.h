/*
 * deadtime_comp_design.h - the configuration of the dead-time compensation
 * (firmware/control/deadtime_comp.h) from an inverter's parameters (the
 * scenario's [inverter] table, sim/model/inverter.h's fields), one design
 * for every drive whose board has an inverter: each drive's host part puts
 * its result into the drive's configuration. Host-side, double precision.
 *
 *   k_bus  = (t_dead + t_on - t_off) f_pwm                       (1) of deadtime_comp.h
 *   V_0, r = the drops of the conducting devices weighted by the fraction
 *            of the period each conducts (J.-W. Choi, S.-K. Sul, IEEE Trans.
 *            Power Electron. 11(2), 1996): complementary MOSFETs, the body
 *            diode in the two dead times f_d = 2 t_dead f_pwm and the channel
 *            the rest; one-way switches (IGBTs) at the duty 1/2 of a leg
 *            about the midpoint, half each
 *   i_band = max(i_transition_A, DTC_NOISE_BANDS i_noise_A): the board's
 *            transition (the node charge over the dead time, or the ripple),
 *            widened where the sensor's noise makes the sign of a smaller
 *            current a guess
 */
#ifndef DESIGN_DEADTIME_COMP_DESIGN_H
#define DESIGN_DEADTIME_COMP_DESIGN_H

#include <stdbool.h>
#include <stddef.h>

#include "control/deadtime_comp.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Noise spreads (standard deviations, or half-widths of uniform noise)
 * within which the measured current's sign is taken as unknown: 3 sigma
 * holds 99.7 % of Gaussian noise. */
#define DTC_NOISE_BANDS 3.0

typedef struct {
    double f_pwm_Hz, dead_time_s, t_on_s, t_off_s;
    double v_switch_V, r_switch_Ohm, v_diode_V, r_diode_Ohm;
    double i_transition_A;
    bool synchronous;
    double i_noise_A; /* the current sensor's noise (sigma or half-width); 0: none */
} deadtime_comp_design_input_t;

/* *out enabled with the coefficients above; false with a reason in err for
 * a value a leg cannot have (f_pwm <= 0, a negative time or drop, an error
 * time of half a period or more). */
bool deadtime_comp_design(const deadtime_comp_design_input_t *in, deadtime_comp_config_t *out, char *err, size_t n);

/* The compensation from an inverter measured on its board
 * (design/inverter_fit.h: firmware/startup/inverter_id.h's levels, issue
 * 45) rather than from a datasheet: the leg's error voltage V, measured
 * on a bus of v_bus_V, as the share of the bus k_bus = V / v_bus_V (the
 * dead time's part, which scales with the bus, is most of it; the body
 * diodes' constant drop is lumped in at that bus), no separate drop or
 * slope (the fitted R already holds the devices' slope: the drive's model
 * carries it), i_band = max(i_tr, DTC_NOISE_BANDS i_noise_A). False with
 * a reason for a fit without an error voltage or a bus <= 0. */
struct inverter_fit;
bool deadtime_comp_from_fit(const struct inverter_fit *f, double v_bus_V, double i_noise_A, deadtime_comp_config_t *out,
                            char *err, size_t n);

#ifdef __cplusplus
}
#endif

#endif /* DESIGN_DEADTIME_COMP_DESIGN_H */
