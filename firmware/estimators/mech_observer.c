#include "estimators/mech_observer.h"

void mech_observer_init(mech_observer_t *m, const mech_observer_config_t *cfg)
{
    m->cfg = *cfg;
    mech_observer_reset(m, MC_ZERO);
}

void mech_observer_reset(mech_observer_t *m, mc_t omega_rad_s)
{
    m->omega_hat_rad_s = omega_rad_s;
    m->tau_hat_Nm = MC_ZERO;
    m->accel_est_rad_s2 = MC_ZERO;
    m->omega_est_rad_s = omega_rad_s;
    m->load_est_Nm = MC_ZERO;
}

void mech_observer_step(mech_observer_t *m, const motor_model_t *model, mc_t omega_meas_rad_s, mc_t i_q_A)
{
    const mech_observer_config_t *c = &m->cfg;
    const mc_t e = mc_sub(omega_meas_rad_s, m->omega_hat_rad_s);
    /* net torque of (33) at the estimates */
    const mc_t tau_net = mc_add(mc_cross2(model->K_V_s, i_q_A, model->fv_Nm_s, m->omega_hat_rad_s), m->tau_hat_Nm);
    m->accel_est_rad_s2 = mc_mul(model->inv_J, tau_net);
    m->load_est_Nm = mc_neg(m->tau_hat_Nm);
    /* (35): model + super-twisting root term + linear term */
    const mc_t inj = mc_dot2(c->lambda_ts, mc_sqrt_abs_sgn(e), c->l_ts, e);
    m->omega_est_rad_s = mc_add(m->omega_hat_rad_s, inj);
    m->omega_hat_rad_s = mc_mac(m->omega_est_rad_s, model->ts_over_J, tau_net);
    m->tau_hat_Nm = mc_clamp(mc_add(m->tau_hat_Nm, mc_mul_sgn(c->alpha_Nm, e)), mc_neg(c->tau_max_Nm), c->tau_max_Nm);
}
