#include "model/iron_model.h"

bool iron_model_init(iron_model_config_t *cfg, mc_t Ld0_H, mc_t Lq0_H, mc_t psi_Wb, mc_t i_sat_A, mc_t i_bias_A)
{
    cfg->Ld0_H = Ld0_H;
    cfg->Lq0_H = Lq0_H;
    cfg->psi_Wb = psi_Wb;
    cfg->inv_isat2_per_A2 = MC_ZERO;
    cfg->lq_over_ld = MC_ONE;
    cfg->i_bias_A = MC_ZERO;
    cfg->k0 = MC_ONE;
    if (!mc_gt(Ld0_H, MC_ZERO) || !mc_gt(Lq0_H, MC_ZERO) || !mc_gt(psi_Wb, MC_ZERO) || !mc_ge(i_sat_A, MC_ZERO) ||
        !mc_ge(i_bias_A, MC_ZERO) || (mc_gt(i_bias_A, MC_ZERO) && mc_eq(i_sat_A, MC_ZERO))) {
        return false;
    }
    cfg->lq_over_ld = mc_div(Lq0_H, Ld0_H);
    if (mc_gt(i_sat_A, MC_ZERO)) {
        cfg->inv_isat2_per_A2 = mc_div(MC_ONE, mc_mul(i_sat_A, i_sat_A));
        cfg->i_bias_A = i_bias_A;
        /* k(0, 0): (S2) at zero current, u_b/u_s = (i_b / i_sat)^2 */
        cfg->k0 = iron_model_factor(cfg, MC_ZERO, MC_ZERO);
    }
    return true;
}

mc_t iron_model_factor(const iron_model_config_t *cfg, mc_t i_d_A, mc_t i_q_A)
{
    /* k = 1 / sqrt(1 + u_b/u_s) (S2), u_b/u_s = ((i_d + i_b)^2 + (L_q0/L_d0) i_q^2) / i_sat^2 */
    const mc_t i_db = mc_add(i_d_A, cfg->i_bias_A);
    const mc_t u = mc_mul(mc_mac(mc_mul(i_db, i_db), cfg->lq_over_ld, mc_mul(i_q_A, i_q_A)), cfg->inv_isat2_per_A2);
    return mc_rsqrt(mc_add(MC_ONE, u));
}

void iron_model_at(const iron_model_config_t *cfg, mc_t i_d_A, mc_t i_q_A, iron_model_point_t *pt)
{
    const mc_t k = iron_model_factor(cfg, i_d_A, i_q_A);
    pt->Lds_H = mc_mul(k, cfg->Ld0_H);
    pt->Lqs_H = mc_mul(k, cfg->Lq0_H);
    /* psi_d = Phi + L_d0 (k (i_d + i_b) - k_0 i_b) = psi_s + k L_d0 i_d (S2) */
    pt->psi_s_Wb = mc_mac(cfg->psi_Wb, mc_mul(cfg->Ld0_H, mc_sub(k, cfg->k0)), cfg->i_bias_A);
    /* (I1): (S3)'s diagonal, (1/k) (1/L_d0 + (i_d + i_b)^2 / (L_d0 i_sat^2)) and
     * (1/k) (1/L_q0 + i_q^2 / (L_d0 i_sat^2)), inverted */
    const mc_t i_db = mc_add(i_d_A, cfg->i_bias_A);
    const mc_t x_d = mc_mul(mc_mul(i_db, i_db), cfg->inv_isat2_per_A2);
    const mc_t x_q = mc_mul(mc_mul(cfg->lq_over_ld, mc_mul(i_q_A, i_q_A)), cfg->inv_isat2_per_A2);
    pt->Ldi_H = mc_div(pt->Lds_H, mc_add(MC_ONE, x_d));
    pt->Lqi_H = mc_div(pt->Lqs_H, mc_add(MC_ONE, x_q));
}
