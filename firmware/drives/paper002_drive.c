#include "drives/paper002_drive.h"

#include "adapter/phase_adapter.h"
#include "math/frame_fg.h"

/* 1/sqrt(3): the largest phase voltage amplitude with min/max zero
 * sequence is v_bus/sqrt(3) */
#define P002_INV_SQRT3 MC_C(0.57735026918962576)

bool paper002_drive_init(paper002_drive_t *d, const paper002_config_t *cfg)
{
    d->cfg = *cfg;
    d->fault = DRIVE_FAULT_NONE;
    d->tick = 0;
    const bool ok = ekf_ipmsm_init(&d->ekf, &cfg->ekf) && sosmc_init(&d->sosmc, &cfg->sosmc) &&
                    htsmc_init(&d->htsmc, &cfg->htsmc) && ibcc_init(&d->ibcc, &cfg->ibcc) &&
                    mc_gt(cfg->i_trip_A, MC_ZERO);
    if (!ok) {
        d->fault = DRIVE_FAULT_BAD_INPUT;
    }
    return ok;
}

static bool p002_zero(paper002_drive_t *d, hal_command_t *out)
{
    out->n_phases = 3u;
    out->v_V[0] = out->v_V[1] = out->v_V[2] = MC_ZERO;
    d->tick += 1u;
    return false;
}

bool paper002_drive_step(paper002_drive_t *d, const hal_sample_t *in, hal_command_t *out)
{
    const paper002_config_t *c = &d->cfg;
    if (d->fault != DRIVE_FAULT_NONE) {
        return p002_zero(d, out);
    }
    if (!phase_adapter_accepts(in, 3u) || !in->has_angle) {
        d->fault = DRIVE_FAULT_BAD_INPUT;
        return p002_zero(d, out);
    }
    for (uint32_t k = 0; k < 3u; ++k) {
        if (!mc_lt(mc_abs(in->i_A[k]), c->i_trip_A)) {
            d->fault = DRIVE_FAULT_OVERCURRENT;
            return p002_zero(d, out);
        }
    }
    /* 1. d-q currents with the encoder's electrical angle */
    mc_t i_zero;
    const mc_ab_t i_ab = phase_adapter_currents(in, &i_zero);
    (void)i_zero;
    const mc_rot_t r_meas = mc_rot_from_angle(mc_elec_angle(in->angle_rad, c->ekf.p));
    mc_t i_d, i_q;
    mc_rot_fwd(r_meas, i_ab.alpha, i_ab.beta, &i_d, &i_q);
    /* 2. the EKF's correction */
    (void)ekf_ipmsm_correct(&d->ekf, i_d, i_q, in->angle_rad);
    const mc_t *x = d->ekf.x;
    d->last.i_d_hat_A = x[EKF_ID];
    d->last.i_q_hat_A = x[EKF_IQ];
    d->last.theta_hat_rad = x[EKF_THETA];
    d->last.w_hat_rad_s = x[EKF_OMEGA];
    d->last.M0_hat_Nm = x[EKF_M0];
    /* 3. reference and torque demand */
    mc_t w_d, dw_d;
    speed_poly_eval(&c->reference, d->tick, &w_d, &dw_d);
    const mc_t M_d = (c->controller == P002_SOSMC)
                         ? sosmc_step(&d->sosmc, &c->sosmc, w_d, dw_d, x[EKF_OMEGA], ekf_ipmsm_accel(&d->ekf), x[EKF_M0])
                         : htsmc_step(&d->htsmc, &c->htsmc, w_d, dw_d, x[EKF_OMEGA], x[EKF_M0]);
    /* 4. MTPA */
    mtpa_out_t ref;
    mtpa_step(&c->mtpa, M_d, &ref);
    /* 5. current control on the EKF's currents and speed */
    const mc_t u_max = mc_mul(in->v_bus_V, P002_INV_SQRT3);
    mc_t u_d, u_q;
    ibcc_step(&d->ibcc, &c->ibcc, ref.i_d_A, ref.i_q_A, x[EKF_ID], x[EKF_IQ], x[EKF_OMEGA], u_max, &u_d, &u_q);
    /* 6. back to alpha-beta at the angle the voltage acts around: the
     * estimate advanced by half a sample */
    const mc_t th_el = mc_elec_angle(mc_mac(x[EKF_THETA], mc_div_i(c->ekf.ts_s, 2), x[EKF_OMEGA]), c->ekf.p);
    mc_ab_t u_ab;
    mc_rot_inv(mc_rot_from_angle(th_el), u_d, u_q, &u_ab.alpha, &u_ab.beta);
    phase_adapter_voltages(3u, u_ab, out);
    /* 7. the EKF's prediction with the voltage applied */
    ekf_ipmsm_predict(&d->ekf, u_d, u_q);
    d->last.w_d_rad_s = w_d;
    d->last.M_d_Nm = M_d;
    d->last.i_dd_A = ref.i_d_A;
    d->last.i_qd_A = ref.i_q_A;
    d->last.i_d_A = i_d;
    d->last.i_q_A = i_q;
    d->last.u_d_V = u_d;
    d->last.u_q_V = u_q;
    d->last.saturated = d->ibcc.saturated;
    d->tick += 1u;
    return true;
}
