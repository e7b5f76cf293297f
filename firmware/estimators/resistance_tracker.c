#include "estimators/resistance_tracker.h"

bool resistance_tracker_init(resistance_tracker_t *t, const resistance_tracker_config_t *cfg)
{
    t->cfg = *cfg;
    t->acc_R_ohm = MC_ZERO;
    t->acc_Phi = MC_ZERO;
    t->R_ohm = cfg->R0_ohm;
    t->Phi_rel = MC_ONE;
    t->e_q_V = MC_ZERO;
    t->i_prev_A.alpha = MC_ZERO;
    t->i_prev_A.beta = MC_ZERO;
    t->u_prev.c = MC_ONE;
    t->u_prev.s = MC_ZERO;
    t->primed = false;
    const bool ok = !cfg->enabled ||
                    (mc_ge(cfg->R0_ohm, MC_ZERO) && mc_gt(cfg->L_fs_ohm, MC_ZERO) && mc_gt(cfg->Phi0_fs_V, MC_ZERO) &&
                     mc_gt(cfg->K_e_V_s, MC_ZERO) && mc_gt(cfg->v_gate2_V2, MC_ZERO) && mc_gt(cfg->e_clamp_V, MC_ZERO) &&
                     mc_gt(cfg->dR_max_ohm, MC_ZERO) && mc_gt(cfg->dPhi_rel_max, MC_ZERO) &&
                     mc_lt(cfg->dPhi_rel_max, MC_ONE) && cfg->n_tau >= 1);
    if (!ok) {
        t->cfg.enabled = false;
    }
    return ok;
}

void resistance_tracker_step(resistance_tracker_t *t, mc_ab_t v_V, mc_ab_t i_A, mc_rot_t u, mc_t omega_mech_rad_s,
                             bool adapt)
{
    const resistance_tracker_config_t *c = &t->cfg;
    if (!c->enabled) {
        return;
    }
    if (t->primed) {
        /* q_hat of the sample's middle: J (u[k-1] + u[k]) / 2 = (-s, c) */
        const mc_t qa = mc_neg(mc_div_i(mc_add(t->u_prev.s, u.s), 2));
        const mc_t qb = mc_div_i(mc_add(t->u_prev.c, u.c), 2);
        /* the sample's mean current (trapezoid) and L di/dt as (L/Ts) delta i */
        const mc_t ia = mc_div_i(mc_add(t->i_prev_A.alpha, i_A.alpha), 2);
        const mc_t ib = mc_div_i(mc_add(t->i_prev_A.beta, i_A.beta), 2);
        const mc_t dia = mc_sub(i_A.alpha, t->i_prev_A.alpha);
        const mc_t dib = mc_sub(i_A.beta, t->i_prev_A.beta);
        const mc_t i_q = mc_dot2(ia, qa, ib, qb);
        /* the back-EMF: (Phi_hat/Ts) sin(angle step), u[k-1] x u[k] */
        const mc_t step = mc_cross2(t->u_prev.c, u.s, t->u_prev.s, u.c);
        const mc_t emf = mc_mul(mc_mul(c->Phi0_fs_V, t->Phi_rel), step);
        /* e_q = (v - R_hat i - L di/dt) . q_hat - omega_e Phi_hat (header) */
        const mc_t v_q = mc_dot2(v_V.alpha, qa, v_V.beta, qb);
        const mc_t ldi_q = mc_mul(c->L_fs_ohm, mc_dot2(dia, qa, dib, qb));
        const mc_t e_q = mc_sub(mc_sub(mc_sub(v_q, mc_mul(t->R_ohm, i_q)), ldi_q), emf);
        t->e_q_V = e_q;
        if (adapt) {
            /* each parameter its share of e_q (header), accumulated unscaled */
            const mc_t v_r = mc_mul(c->R0_ohm, i_q);              /* R0 i_q */
            const mc_t v_e = mc_mul(c->K_e_V_s, omega_mech_rad_s); /* K_e w_hat */
            const mc_t m2 = mc_max(mc_dot2(v_r, v_r, v_e, v_e), c->v_gate2_V2);
            const mc_t e = mc_div(mc_clamp(e_q, mc_neg(c->e_clamp_V), c->e_clamp_V), m2);
            const mc_t r_hi = mc_mul_i(c->dR_max_ohm, c->n_tau);
            const mc_t r_lo = mc_max(mc_neg(r_hi), mc_neg(mc_mul_i(c->R0_ohm, c->n_tau))); /* R_hat >= 0 */
            const mc_t p_hi = mc_mul_i(c->dPhi_rel_max, c->n_tau);
            t->acc_R_ohm = mc_clamp(mc_add(t->acc_R_ohm, mc_mul(mc_mul(e, v_r), c->R0_ohm)), r_lo, r_hi);
            t->acc_Phi = mc_clamp(mc_add(t->acc_Phi, mc_mul(e, v_e)), mc_neg(p_hi), p_hi);
            t->R_ohm = mc_add(c->R0_ohm, mc_div_i(t->acc_R_ohm, c->n_tau));
            t->Phi_rel = mc_add(MC_ONE, mc_div_i(t->acc_Phi, c->n_tau));
        }
    }
    t->i_prev_A = i_A;
    t->u_prev = u;
    t->primed = true;
}
