#include "control/load_angle.h"

void load_angle_init(load_angle_t *c, const load_angle_config_t *cfg)
{
    c->cfg = *cfg;
    c->int_f_V = MC_ZERO;
    c->int_g_V = MC_ZERO;
    c->load_Nm = MC_ZERO;
    c->i_amp_A = cfg->i_s_A;
    c->i_f_ref_A = MC_ZERO;
    c->i_g_ref_A = MC_ZERO;
}

void load_angle_start(load_angle_t *c, mc_t i_A)
{
    c->i_amp_A = mc_clamp(i_A, MC_ZERO, c->cfg.i_s_A);
    c->int_f_V = MC_ZERO;
    c->int_g_V = MC_ZERO;
}

void load_angle_step(load_angle_t *c, const motor_model_t *m, const trajectory_point_t *r, mc_t i_f_A, mc_t i_g_A,
                     bool has_estimate, mc_t omega_est_rad_s, mc_t load_est_Nm, bool hold_integral, mc_t *v_f_V,
                     mc_t *v_g_V)
{
    const load_angle_config_t *k = &c->cfg;
    /* the torque the reference needs, (39) with the load of (9c):
     * J w_r' = K i_g - f_v w_r - C_r; the load as last observed */
    const mc_t load_prev = c->load_Nm;
    /* w = n_p L w_r [ohm] and e = K w_r [V] of (38), used by the cut and the voltage */
    const mc_t npLw = mc_mul(m->npL_ohm_s, r->omega_rad_s);
    const mc_t e = mc_mul(m->K_V_s, r->omega_rad_s);
    if (has_estimate) {
        /* towards the observed load at a bounded rate: the estimate arrives
         * as a jump when the loop closes on a load the open loop carried */
        const mc_t target = mc_clamp(load_est_Nm, mc_neg(k->load_ff_max_Nm), k->load_ff_max_Nm);
        c->load_Nm = mc_add(c->load_Nm, mc_clamp(mc_sub(target, c->load_Nm), mc_neg(k->load_slew_Nm), k->load_slew_Nm));
    }
    const mc_t i_ff = mc_dot2(m->J_over_K_A_s2, r->accel_rad_s2, m->fv_over_K_A_s, r->omega_rad_s);
    const mc_t i_load = mc_div(c->load_Nm, m->K_V_s);
    mc_t i_g = mc_add(i_ff, i_load);
    /* L di_g,r/dt of (38) for the fed-forward load's change over the sample
     * (the reference's own, (JL/K) theta_r''', is under 2 mV for the rig's
     * moves and left to the PI) */
    const mc_t Ldi_g = mc_mul(k->L_over_KTs_V_per_Nm, mc_sub(c->load_Nm, load_prev));
    if (has_estimate) {
        /* damping on the observed speed: the spring alone rings at
         * sqrt(n_p K I_s / J) with the motor's own f_v only */
        i_g = mc_sub(i_g, mc_mul(k->damp_A_s_per_rad, mc_sub(omega_est_rad_s, r->omega_rad_s)));
    }
    /* the amplitude: I_s, or ramping there after a hand-over */
    if (mc_lt(c->i_amp_A, k->i_s_A)) {
        c->i_amp_A = mc_min(k->i_s_A, mc_add(c->i_amp_A, k->i_amp_slew_A));
    }
    const mc_t i_amp = c->i_amp_A;
    const mc_t i_g_max = mc_min(k->i_g_max_A, i_amp);
    i_g = mc_clamp(i_g, mc_neg(i_g_max), i_g_max);
    /* the rest of the amplitude on the reference's f axis: the spring */
    mc_t i_f = mc_sqrt(mc_max(MC_ZERO, mc_sub(mc_mul(i_amp, i_amp), mc_mul(i_g, i_g))));
    const mc_t z2 = mc_dot2(m->R_ohm, m->R_ohm, npLw, npLw);
    if (mc_gt(k->v_limit_V, MC_ZERO) && mc_gt(z2, MC_ZERO)) {
        /* as much of it as the supply drives at this speed: the steady
         * state of (38) at (i_f, i_g), w = n_p L w_r, e = K w_r, Z^2 = R^2 + w^2,
         *   |v|^2 = Z^2 (i_f^2 + i_g^2) + e^2 + 2 e (R i_g + w i_f) <= V^2,
         * solved for the largest i_f (Z = 0, a motor model without R at
         * rest, needs no voltage: nothing to cut) */
        const mc_t c0 = mc_sub(mc_add(mc_mul(z2, mc_mul(i_g, i_g)), mc_mac(mc_mul(e, e), mc_mul_i(e, 2), mc_mul(m->R_ohm, i_g))),
                               mc_mul(k->v_limit_V, k->v_limit_V));
        /* i_f = -a + sqrt(a^2 - b), a = e w / Z^2 [A], b = c0 / Z^2 [A^2]:
         * divided first, so that no term exceeds a few hundred (the fixed
         * format's range is +-16384; e^2 w^2 alone is 2,200 for the rig) */
        const mc_t a = mc_div(mc_mul(e, npLw), z2);
        const mc_t disc = mc_sub(mc_mul(a, a), mc_div(c0, z2));
        const mc_t i_f_v = mc_gt(disc, MC_ZERO) ? mc_sub(mc_sqrt(disc), a) : MC_ZERO;
        i_f = mc_max(MC_ZERO, mc_min(i_f, i_f_v));
    }
    c->i_f_ref_A = i_f;
    c->i_g_ref_A = i_g;

    /* PI on the current errors, the integral held while the output saturates */
    const mc_t e_f = mc_sub(i_f, i_f_A);
    const mc_t e_g = mc_sub(i_g, i_g_A);
    if (!hold_integral) {
        c->int_f_V = mc_mac(c->int_f_V, k->ki_ohm, e_f);
        c->int_g_V = mc_mac(c->int_g_V, k->ki_ohm, e_g);
    }
    /* the reference model (38) at the references, plus the PI:
     *   v_f = R i_f,r - n_p L w_r i_g,r
     *   v_g = R i_g,r + n_p L w_r i_f,r + K w_r + L di_g,r/dt */
    const mc_t v_f = mc_cross2(m->R_ohm, i_f, npLw, i_g);
    const mc_t v_g = mc_add(mc_add(mc_dot2(m->R_ohm, i_g, npLw, i_f), e), Ldi_g);
    *v_f_V = mc_add(v_f, mc_mac(c->int_f_V, k->kp_ohm, e_f));
    *v_g_V = mc_add(v_g, mc_mac(c->int_g_V, k->kp_ohm, e_g));
}
