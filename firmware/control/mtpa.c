#include "control/mtpa.h"

mc_t mtpa_id_of_iq(const motor_model_t *m, mc_t i_q_A)
{
    const mc_t dL = mc_sub(m->Ld_H, m->Lq_H);
    if (mc_eq(dL, MC_ZERO)) {
        return MC_ZERO;
    }
    /* (18): i_d = -a/2 - sign(-a) 1/2 sqrt(a^2 + 4 i_q^2), a = psi/dL; the
     * root with |i_d| smallest (i_d = 0 at i_q = 0, towards -inf for L_d < L_q) */
    const mc_t a = mc_div(m->psi_Wb, dL);
    const mc_t r = mc_sqrt(mc_add(mc_mul(a, a), mc_mul_i(mc_mul(i_q_A, i_q_A), 4)));
    const mc_t half = MC_C(0.5);
    return mc_lt(a, MC_ZERO) ? mc_mul(half, mc_sub(mc_neg(a), r)) : mc_mul(half, mc_sub(r, a));
}

mc_t mtpa_torque(const motor_model_t *m, mc_t i_d_A, mc_t i_q_A)
{
    /* (10): 3/2 p (psi i_q + (L_d - L_q) i_d i_q) */
    const mc_t flux = mc_mac(m->psi_Wb, mc_sub(m->Ld_H, m->Lq_H), i_d_A);
    return mc_mul(mc_mul_i(mc_mul(MC_C(1.5), flux), m->n_p), i_q_A);
}

void mtpa_step(const mtpa_config_t *c, const motor_model_t *m, mc_t M_d_Nm, mtpa_out_t *out)
{
    const mc_t k = mc_mul_i(MC_C(1.5), m->n_p); /* 3/2 p */
    const mc_t dL = mc_sub(m->Ld_H, m->Lq_H);
    mc_t iq = mc_div(M_d_Nm, mc_mul(k, m->psi_Wb));
    mc_t id = MC_ZERO;
    if (!mc_eq(dL, MC_ZERO)) {
        const mc_t a = mc_div(m->psi_Wb, dL);
        for (int n = 0; n < MTPA_NEWTON_STEPS; ++n) {
            id = mtpa_id_of_iq(m, iq);
            const mc_t r = mc_sqrt(mc_add(mc_mul(a, a), mc_mul_i(mc_mul(iq, iq), 4)));
            /* d i_d / d i_q = -+2 i_q / r (the sign of the root of mtpa_id_of_iq) */
            mc_t did = mc_gt(r, MC_ZERO) ? mc_div(mc_mul_i(iq, 2), r) : MC_ZERO;
            did = mc_lt(a, MC_ZERO) ? mc_neg(did) : did;
            const mc_t g = mc_sub(mtpa_torque(m, id, iq), M_d_Nm);
            const mc_t dg = mc_mul(k, mc_mac(m->psi_Wb, dL, mc_mac(id, iq, did)));
            if (!mc_gt(mc_abs(dg), MC_ZERO)) {
                break;
            }
            iq = mc_sub(iq, mc_div(g, dg));
        }
        id = mtpa_id_of_iq(m, iq);
    }
    /* |i| <= i_max along the curve: the i_q on the curve with |i| = i_max,
     * by bisection on [0, |i_q|] (|i| grows with |i_q| along the curve);
     * MTPA_LIMIT_STEPS halvings */
    out->limited = mc_gt(mc_hypot(id, iq), c->i_max_A);
    if (out->limited) {
        const bool neg = mc_lt(iq, MC_ZERO);
        mc_t lo = MC_ZERO, hi = mc_abs(iq);
        for (int n = 0; n < MTPA_LIMIT_STEPS; ++n) {
            const mc_t mid = mc_div_i(mc_add(lo, hi), 2);
            if (mc_gt(mc_hypot(mtpa_id_of_iq(m, mid), mid), c->i_max_A)) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        iq = neg ? mc_neg(lo) : lo;
        id = mtpa_id_of_iq(m, iq);
    }
    out->i_d_A = id;
    out->i_q_A = iq;
}
