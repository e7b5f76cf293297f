#include "startup/k_identification.h"

void k_id_init(k_id_t *k, const k_id_config_t *cfg)
{
    k->cfg = *cfg;
    k->state = cfg->enabled ? K_ID_RUNNING : K_ID_OFF;
    k->n = 0;
    k->m_ex_V = MC_ZERO;
    k->m_x2 = MC_ZERO;
    k->K_V_s = cfg->K_model_V_s;
}

bool k_id_step(k_id_t *k, mc_t e2_V2, mc_t omega_ref_rad_s)
{
    if (k->state != K_ID_RUNNING) {
        return false;
    }
    const mc_t w = mc_abs(omega_ref_rad_s);
    if (mc_lt(w, k->cfg.w_min_rad_s)) {
        return false;
    }
    const mc_t x = mc_min(mc_mul(w, k->cfg.inv_w_scale_s), MC_ONE);
    k->n += 1;
    /* running means m += (v - m)/n */
    k->m_ex_V = mc_add(k->m_ex_V, mc_div_i(mc_sub(mc_mul(mc_sqrt(e2_V2), x), k->m_ex_V), k->n));
    k->m_x2 = mc_add(k->m_x2, mc_div_i(mc_sub(mc_mul(x, x), k->m_x2), k->n));
    if (k->n < k->cfg.n_window) {
        return false;
    }
    /* K = mean(|e| x) / mean(x^2) / w_scale */
    const mc_t K = mc_mul(mc_div(k->m_ex_V, k->m_x2), k->cfg.inv_w_scale_s);
    const mc_t Km = k->cfg.K_model_V_s;
    const bool ok = !mc_lt(K, mc_mul(Km, MC_C(0.5))) && !mc_gt(K, mc_mul(Km, MC_C(2.0)));
    const bool differs = mc_gt(mc_abs(mc_sub(K, Km)), mc_mul(Km, k->cfg.deadband));
    k->state = !ok ? K_ID_REJECTED : (differs ? K_ID_DONE : K_ID_KEPT);
    if (ok) {
        k->K_V_s = K;
    }
    return true;
}
