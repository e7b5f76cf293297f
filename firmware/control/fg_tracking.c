#include "control/fg_tracking.h"

void fg_tracking_init(fg_tracking_t *t, const fg_tracking_config_t *cfg)
{
    t->cfg = *cfg;
    super_twisting_init(&t->cur, &cfg->cur);
    twisting_init(&t->pos, &cfg->pos);
    t->i_f_off_A = MC_ZERO;
    t->i_g_off_A = MC_ZERO;
    t->i_f_ref_A = MC_ZERO;
    t->i_g_ref_A = MC_ZERO;
    t->load_ff_Nm = MC_ZERO;
}

/* Reference currents and voltages of the flat outputs, eqs. (38)-(39):
 * i_g,r = (J theta_r'' + f_v theta_r')/K, and the voltages from the
 * reference model (38) with i_f,r constant. */
/* The reference currents alone (the first half of
 * fg_tracking_references, which fg_tracking_start needs without the
 * voltages); returns the clamped load C_r of the feed-forward. */
static inline mc_t fg_tracking_currents(const fg_tracking_t *t, const motor_model_t *m, mc_t i_max_A,
                                        const trajectory_point_t *r, mc_t load_est_Nm, mc_t *i_fr, mc_t *i_gr)
{
    const fg_tracking_config_t *c = &t->cfg;
    /* i_f,r: constant plus the decaying switch offset (a free flat output) */
    *i_fr = mc_add(c->i_f_ref_A, t->i_f_off_A);
    /* (39) with the load of (9c): J w_r' = K i_g,r - f_v w_r - C_r, C_r from (35) */
    mc_t i_g = mc_dot2(m->J_over_K_A_s2, r->accel_rad_s2, m->fv_over_K_A_s, r->omega_rad_s);
    const mc_t load_ff = mc_clamp(load_est_Nm, mc_neg(c->load_ff_max_Nm), c->load_ff_max_Nm);
    i_g = mc_mac(i_g, c->load_ff_A_per_Nm, load_ff);
    *i_gr = mc_clamp(mc_add(i_g, t->i_g_off_A), mc_neg(i_max_A), i_max_A);
    return load_ff;
}

void fg_tracking_references(fg_tracking_t *t, const motor_model_t *m, mc_t i_max_A, const trajectory_point_t *r,
                            const trajectory_point_t *rn, mc_t load_est_Nm, mc_t *i_fr, mc_t *i_gr, mc_t *v_fr,
                            mc_t *v_gr)
{
    const fg_tracking_config_t *c = &t->cfg;
    const mc_t load_ff = fg_tracking_currents(t, m, i_max_A, r, load_est_Nm, i_fr, i_gr);
    /* L di_g,r/dt of (39), (JL/K) theta_r''' + (L f_v/K) theta_r'', taken as
     * the change of i_g,r over the sample (L/Ts times the difference of the
     * references at k+1 and k): the voltage is held over that sample, so its
     * average is what moves the current there */
    mc_t Ldi_gr = mc_dot2(m->LJ_over_KTs_V_s2, mc_sub(rn->accel_rad_s2, r->accel_rad_s2), m->Lfv_over_KTs_V_s,
                          mc_sub(rn->omega_rad_s, r->omega_rad_s));
    if (mc_ne(c->load_ff_L_over_KTs, MC_ZERO)) {
        /* and of the fed-forward C_r/K: (L/K) dC_r/dt, the change since the
         * last call (the discrete-time design; the continuous one leaves it
         * to the twisting loop as the dC_r/dt of (56)) */
        Ldi_gr = mc_mac(Ldi_gr, c->load_ff_L_over_KTs, mc_sub(load_ff, t->load_ff_Nm));
        t->load_ff_Nm = load_ff;
    }
    mc_t Ldi_fr = MC_ZERO;
    if (mc_ne(t->i_f_off_A, MC_ZERO) || mc_ne(t->i_g_off_A, MC_ZERO)) {
        Ldi_fr = mc_neg(mc_mul(c->ref_blend_L_over_tau_ohm, t->i_f_off_A));
        Ldi_gr = mc_sub(Ldi_gr, mc_mul(c->ref_blend_L_over_tau_ohm, t->i_g_off_A));
    }
    const mc_t npLw = mc_mul(m->npL_ohm_s, r->omega_rad_s);
    /* L di_f,r/dt = v_f,r - R i_f,r + n_p L w_r i_g,r   (38) */
    *v_fr = mc_add(mc_cross2(m->R_ohm, *i_fr, npLw, *i_gr), Ldi_fr);
    /* L di_g,r/dt = v_g,r - R i_g,r - n_p L w_r i_f,r - K w_r   (38) */
    *v_gr = mc_mac(mc_add(Ldi_gr, mc_dot2(m->R_ohm, *i_gr, npLw, *i_fr)), m->K_V_s, r->omega_rad_s);
}

void fg_tracking_start(fg_tracking_t *t, const motor_model_t *m, mc_t i_max_A, const trajectory_point_t *ref,
                       const trajectory_point_t *ref_next, mc_t load_est_Nm, mc_t i_d_A, mc_t i_q_A)
{
    (void)ref_next; /* the voltages of the switch sample come from fg_tracking_step */
    super_twisting_reset(&t->cur, MC_ZERO);
    t->i_f_off_A = MC_ZERO;
    t->i_g_off_A = MC_ZERO;
    /* the references' currents at the switch, without their voltages
     * (fg_tracking_references would also store this clamped load as
     * load_ff_Nm: the same value) */
    mc_t i_fr0, i_gr0;
    t->load_ff_Nm = fg_tracking_currents(t, m, i_max_A, ref, load_est_Nm, &i_fr0, &i_gr0);
    t->i_f_off_A = mc_sub(i_d_A, i_fr0);
    t->i_g_off_A = mc_sub(i_q_A, i_gr0);
}
