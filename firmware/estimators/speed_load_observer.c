#include "estimators/speed_load_observer.h"

void speed_load_observer_init(speed_load_observer_t *o, const speed_load_observer_config_t *cfg, mc_rot_t rho0,
                              mc_t omega0_rad_s, mc_t load0_Nm)
{
    o->cfg = *cfg;
    angle_unwrap_init(&o->unwrap, mc_atan2(rho0.s, rho0.c));
    o->omega_rad_s = omega0_rad_s;
    o->load_Nm = load0_Nm;
    o->i_q_A = MC_ZERO;
}

void speed_load_observer_step(speed_load_observer_t *o, mc_rot_t rho, mc_ab_t i_A)
{
    /* i^T Jm rho = rho_a i_b - rho_b i_a: the current along q of the estimate */
    speed_load_observer_step_iq(o, rho, mc_cross2(rho.c, i_A.beta, rho.s, i_A.alpha));
}

void speed_load_observer_step_iq(speed_load_observer_t *o, mc_rot_t rho, mc_t i_q)
{
    const speed_load_observer_config_t *c = &o->cfg;
    angle_unwrap_step(&o->unwrap, rho.s, rho.c); /* A(rho_b/rho_a), Appendix A */
    /* innovation as a speed: dy fs/n_p - w_hat */
    const mc_t nu = mc_sub(mc_mul(o->unwrap.delta_rad, c->fs_over_np), o->omega_rad_s);
    /* (15)-(16) in the estimates (see the header):
     * w_hat += (Ts/J)(K_t i_q - tau_hat) + a1 n_p Ts nu,  tau_hat -= a2 n_p Ts nu */
    const mc_t dw = mc_sub(mc_mul(c->ts_kt_over_J, i_q), mc_mul(c->ts_over_J, o->load_Nm));
    o->omega_rad_s = mc_add(o->omega_rad_s, mc_mac(dw, c->k_omega, nu));
    o->load_Nm = mc_sub(o->load_Nm, mc_mul(c->k_load_Nm_s, nu));
    o->i_q_A = i_q;
}
