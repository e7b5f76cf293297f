/*
 * deadtime_comp.h - dead-time and device-drop compensation of a PWM
 * inverter (issue 30): given each leg's current and the bus, the average
 * voltage error the inverter will make over the next period; the drive adds
 * its opposite to the leg commands, and what the inverter cannot give (a
 * compensated command beyond the bus) is returned so that the estimator's
 * "applied voltage" carries the expected error. One block for every drive
 * whose board has an inverter; a drive without one leaves it disabled, and a
 * disabled block changes nothing (the drive's arithmetic is then as before,
 * bit for bit).
 *
 * The model, averaged over one PWM period T = 1/f_pwm, a leg whose current
 * i flows out of the leg into the motor (T. Sukegawa, K. Kamiyama,
 * K. Mizuno, T. Matsui, T. Okuyama, "Fully digital, vector-controlled PWM
 * VSI-fed ac drives with an inverter dead-time compensation strategy",
 * IEEE Trans. Ind. Appl. 27(3), 1991, pp. 552-559: the volt-seconds lost
 * per period; J.-W. Choi, S.-K. Sul, "Inverter output voltage synthesis
 * using novel dead time compensation", IEEE Trans. Power Electron. 11(2),
 * 1996, pp. 221-227: the same with the devices' drops):
 *
 *   dv(i) = -( V_dc (t_dead + t_on - t_off) f_pwm + V_0 ) s(i) - r i     (1)
 *
 * V_0 and r the conducting devices' drop and slope resistance weighted by
 * the time each conducts (computed at design time: for complementary
 * MOSFETs the channel but for the two dead times, the body diode in them).
 * s(i) stands for sgn(i), which a drive cannot use as it is: near zero
 * current the measured sign is noise, and a real leg's error goes through
 * zero smoothly over a band of currents. The block uses the transition of
 * the charge-based commutation (docs/plant.md, "The transition near zero
 * current": during the dead time the load current itself swings the node's
 * capacitance, charge Q = 2 Q_oss, across the bus; a current below
 * i_band = Q / t_dead does not finish the swing), with x = i / i_band:
 *
 *   s(x) = x / 2 for |x| <= 1,   sgn(x) (1 - 1/(2 |x|)) for |x| > 1      (2)
 *
 * continuous with a continuous slope, 1/2 at i_band and 0.95 at 10 i_band.
 * A plain ramp clamp(x, -1, 1) (the "trapezoidal" compensation) was tried
 * first: against a leg that commutates as (2) it overcompensates by 10 to
 * 20 % at one to three i_band, and paper 001's flux observer, which
 * integrates the voltage error, drifted 85 electrical degrees on the
 * benchmark's 1 N m step at 50 rpm with it (docs/plant.md).
 * (i_band = 0: the hard sign); i_band is the design's, from the board's
 * transition current and the sensor's noise (design/deadtime_comp_design
 * in the host parts). The compensation of leg k is c_k = -dv(i_k): the
 * command becomes v_k + c_k, clamped to the bus (+-V_dc/2 about the
 * midpoint for a leg; +-V_dc for a two-leg H-bridge winding, whose error
 * is that of two legs carrying +i and -i, twice (1)).
 *
 * What the estimator must add to the voltage it believes it applied (the
 * drive's intended v): the part of the compensation the bus clamp removed,
 * r_k = clamp(v_k + c_k) - (v_k + c_k), through Clarke into alpha-beta (a
 * leg held at a rail has no dead time: its error is smaller than (1) says,
 * which this first-order account ignores). The minimum pulse is not
 * compensated (a pulse it swallows is a few per cent of a volt on these
 * boards).
 *
 * Fixed point (Q14.17, mc_num_fixed.h): k_bus = (t_dead + t_on - t_off)
 * f_pwm is about 1e-2 (357 ns at 20 kHz: 7.1e-3, stored to 0.05 %);
 * k_bus V_dc <= 1 V; x = i / i_band clamped to +-1000 before 1/(2|x|)
 * (i / i_band saturates at the format's edge for absurd currents);
 * r i <= 10 A * 10 mOhm; every intermediate far inside +-16384.
 */
#ifndef CONTROL_DEADTIME_COMP_H
#define CONTROL_DEADTIME_COMP_H

#include <stdbool.h>
#include <stdint.h>

#include "adapter/phase_adapter.h"
#include "hal/hal_types.h"
#include "math/mc_num.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    bool enabled;        /* false: no inverter (or compensation off): the block changes nothing */
    mc_t k_bus;          /* (t_dead + t_on - t_off) f_pwm: the fraction of V_dc lost per leg, (1) */
    mc_t v_drop_V;       /* V_0 of (1): the devices' constant drop, conduction-weighted [V] */
    mc_t r_drop_ohm;     /* r of (1): their slope resistance, conduction-weighted [ohm] */
    mc_t inv_i_band_per_A; /* 1 / i_band of (2) [1/A]; 0: the hard sign */
} deadtime_comp_config_t;

typedef struct {
    deadtime_comp_config_t cfg;
} deadtime_comp_t;

/* Copies cfg. False for a negative coefficient (then disabled). */
bool deadtime_comp_init(deadtime_comp_t *d, const deadtime_comp_config_t *cfg);

/* s(i) of (2) in [-1, 1]. */
mc_t deadtime_comp_sign(const deadtime_comp_t *d, mc_t i_A);

/* dv(i) of (1) for one leg on a bus of v_bus_V [V] (0 when disabled). */
mc_t deadtime_comp_leg_error_V(const deadtime_comp_t *d, mc_t i_A, mc_t v_bus_V);

/* Inputs: the sample's phase currents i_A[0..n-1] (out of the legs; a
 * winding's current for n = 2), the bus v_bus_V, the command *out as the
 * drive formed it (n_phases 2 or 3: out->n_phases). Output: out->v_V[k]
 * compensated and clamped to the bus; returned, the alpha-beta voltage the
 * estimator adds to the voltage it intended (the compensation the clamp
 * removed). Disabled: *out unchanged, returns 0. */
mc_ab_t deadtime_comp_step(const deadtime_comp_t *d, const mc_t *i_A, mc_t v_bus_V, hal_command_t *out);

#ifdef __cplusplus
}
#endif

#endif /* CONTROL_DEADTIME_COMP_H */
