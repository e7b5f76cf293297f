#include "supervisor/lock_monitor.h"

void lock_monitor_init(lock_monitor_t *m, const lock_monitor_config_t *cfg)
{
    m->cfg = *cfg;
    m->run.run = 0;
    m->residual_V = MC_ZERO;
    m->bound_V = MC_ZERO;
    m->innov_count = 0;
    m->innov_ratio = MC_ZERO;
}

lock_criterion_t lock_monitor_step_flux(lock_monitor_t *m, mc_t rho2, mc_t rho2_target, mc_t omega_hat_rad_s,
                                        mc_t i_d_A, mc_t i_q_A)
{
    const lock_monitor_config_t *c = &m->cfg;
    if (c->ticks <= 0) {
        return LOCK_CRIT_NONE;
    }
    /* e_d = gamma Phi^3 |target - |rho|^2| (lock_monitor.h; (12) in steady state) */
    m->residual_V = mc_mul(c->gPhi3_V, mc_abs(mc_sub(rho2_target, rho2)));
    const mc_t w = mc_abs(omega_hat_rad_s);
    const mc_t i = mc_hypot(i_d_A, i_q_A);
    /* k_speed |w| + k_speed_cur |w| |i| + k_cur |i| + floor */
    mc_t b = mc_mac(c->floor_V, c->k_cur_ohm, i);
    b = mc_mac(b, mc_mul(c->k_speed_cur_H, w), i);
    m->bound_V = mc_mac(b, c->k_speed_V_s, w);
    return fault_persist_step(&m->run, mc_gt(m->residual_V, m->bound_V), c->ticks) ? LOCK_CRIT_FLUX_RESIDUAL
                                                                                     : LOCK_CRIT_NONE;
}

lock_criterion_t lock_monitor_step_innovation(lock_monitor_t *m, mc_t nu_rad, mc_t s_rad2, mc_t omega_tol_rad_s)
{
    const lock_monitor_config_t *c = &m->cfg;
    if (c->innov_limit <= 0) {
        return LOCK_CRIT_NONE;
    }
    /* bound^2 = k^2 S + (w_tol Ts)^2 (lock_monitor.h) */
    const mc_t tol_rad = mc_mul(mc_abs(omega_tol_rad_s), c->ts_s);
    const mc_t bound2 = mc_mac(mc_mul(tol_rad, tol_rad), c->innov_k2, s_rad2);
    const mc_t nu2 = mc_mul(nu_rad, nu_rad);
    m->innov_ratio = mc_gt(bound2, MC_ZERO) ? mc_div(nu2, bound2) : nu2;
    if (mc_gt(nu2, bound2)) {
        m->innov_count = (m->innov_count > c->innov_limit - c->innov_up) ? c->innov_limit
                                                                           : m->innov_count + c->innov_up;
    } else if (m->innov_count > 0) {
        m->innov_count -= 1;
    }
    return (m->innov_count >= c->innov_limit) ? LOCK_CRIT_ANGLE_INNOVATION : LOCK_CRIT_NONE;
}
