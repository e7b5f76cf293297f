#include "startup/pmsm_identification.h"

#include "math/mc_mean.h"
#include "startup/open_loop.h"

static bool pmsm_id_reject(pmsm_id_t *id, const char *why)
{
    id->phase = PMSM_ID_REJECTED;
    id->why = why;
    id->R_ohm = id->cfg.model.R_ohm;
    id->L_fs_ohm = mc_mul_i(id->cfg.model.L_H, id->cfg.model.fs_hz);
    id->Phi_Wb = id->cfg.Phi_model_Wb;
    return false;
}

static bool within_factor_two(mc_t x, mc_t ref) { return !mc_lt(x, mc_div_i(ref, 2)) && !mc_gt(x, mc_mul_i(ref, 2)); }

bool pmsm_id_init(pmsm_id_t *id, const pmsm_id_config_t *cfg)
{
    id->cfg = *cfg;
    id->phase = PMSM_ID_ALIGN_BETA;
    id->k = 0;
    rl_id_init(&id->rl, &cfg->rl);
    id->measured = cfg->model;
    id->theta_e_rad = MC_ZERO;
    id->omega_e_rad_s = MC_ZERO;
    id->ramping_down = false;
    id->v_prev_V.alpha = id->v_prev_V.beta = MC_ZERO;
    id->i_prev_A.alpha = id->i_prev_A.beta = MC_ZERO;
    id->mean_e_V = id->res_e = MC_ZERO;
    id->why = "";
    (void)pmsm_id_reject(id, ""); /* results start at the model's values */
    id->phase = PMSM_ID_ALIGN_BETA;
    const bool ok = cfg->model.fs_hz > 0 && cfg->model.n_p >= 1 && mc_gt(cfg->i_trip_A, MC_ZERO) &&
                    mc_gt(cfg->v_align_V, MC_ZERO) && mc_gt(cfg->v_rl_V, MC_ZERO) && mc_gt(cfg->i_spin_A, MC_ZERO) &&
                    mc_gt(cfg->omega_spin_e_rad_s, MC_ZERO) && mc_gt(cfg->theta_step_rad, MC_ZERO) && mc_gt(cfg->omega_step_e_rad_s, MC_ZERO) &&
                    cfg->align_beta_ticks >= 0 && cfg->align_alpha_ticks > 0 && cfg->rest_ticks >= 0 &&
                    cfg->meas_ticks > 0 && cfg->hold_ticks >= cfg->meas_ticks && id->rl.state == RL_ID_RUNNING &&
                    mc_gt(cfg->Phi_model_Wb, MC_ZERO);
    return ok ? true : pmsm_id_reject(id, "configuration");
}

/* Next phase once this one has lasted `ticks` samples. */
static void pmsm_id_advance(pmsm_id_t *id, int32_t ticks, pmsm_id_phase_t next)
{
    if (id->k >= ticks) {
        id->phase = next;
        id->k = 0;
    }
}

/* The spin: (68) along theta_e with the measured R, L; the mean |e| over the
 * last meas_ticks of the hold; ramps of omega_step per sample. True when over. */
static bool pmsm_id_spin(pmsm_id_t *id, mc_ab_t i_ab, mc_ab_t *v)
{
    const pmsm_id_config_t *c = &id->cfg;
    if (!id->ramping_down) {
        if (mc_lt(id->omega_e_rad_s, c->omega_spin_e_rad_s)) {
            id->omega_e_rad_s = mc_min(mc_add(id->omega_e_rad_s, c->omega_step_e_rad_s), c->omega_spin_e_rad_s);
            id->k = 0;
        } else {
            /* held: from the (hold - meas)-th sample on, measure
             * e = v - R i - L di/dt over the last sample (paper 001 (1)) */
            if (id->k >= c->hold_ticks - c->meas_ticks) {
                const mc_t ia = mc_div_i(mc_add(id->i_prev_A.alpha, i_ab.alpha), 2);
                const mc_t ib = mc_div_i(mc_add(id->i_prev_A.beta, i_ab.beta), 2);
                const mc_t ea = mc_sub(mc_sub(id->v_prev_V.alpha, mc_mul(id->R_ohm, ia)),
                                       mc_mul(id->L_fs_ohm, mc_sub(i_ab.alpha, id->i_prev_A.alpha)));
                const mc_t eb = mc_sub(mc_sub(id->v_prev_V.beta, mc_mul(id->R_ohm, ib)),
                                       mc_mul(id->L_fs_ohm, mc_sub(i_ab.beta, id->i_prev_A.beta)));
                mc_mean_add(&id->mean_e_V, &id->res_e, mc_hypot(ea, eb), c->meas_ticks);
            }
            id->k += 1;
            if (id->k >= c->hold_ticks) {
                id->ramping_down = true;
            }
        }
    } else {
        id->omega_e_rad_s = mc_max(mc_sub(id->omega_e_rad_s, c->omega_step_e_rad_s), MC_ZERO);
        if (!mc_gt(id->omega_e_rad_s, MC_ZERO)) {
            v->alpha = v->beta = MC_ZERO;
            return true;
        }
    }
    /* theta_e += w_e Ts, kept in (-pi, pi]; while held, by the configured
     * step itself, whose speed theta_step fs is what Phi is divided by
     * (w_e/fs rounds by up to half an LSB of 7.6e-6 rad in Q14.17: 0.24 %
     * of the step at 50 rpm, n_p = 3, 10 kHz, which would bias Phi as much) */
    const bool held = !id->ramping_down && !mc_lt(id->omega_e_rad_s, c->omega_spin_e_rad_s);
    const mc_t step = held ? c->theta_step_rad : mc_div_i(id->omega_e_rad_s, c->model.fs_hz);
    id->theta_e_rad = mc_add(id->theta_e_rad, step);
    if (mc_gt(id->theta_e_rad, MC_PI)) {
        id->theta_e_rad = mc_sub(id->theta_e_rad, MC_TWO_PI);
    }
    open_loop_config_t ol;
    ol.i_max_A = c->i_spin_A;
    ol.v_max_V = MC_C(1000.0); /* no cap: the bus limits below */
    const mc_t mag = open_loop_voltage(&ol, &id->measured, mc_div_i(id->omega_e_rad_s, c->model.n_p));
    const mc_rot_t u = mc_rot_from_angle(id->theta_e_rad);
    v->alpha = mc_mul(mag, u.c);
    v->beta = mc_mul(mag, u.s);
    return false;
}

bool pmsm_id_step(pmsm_id_t *id, mc_ab_t i_ab_A, const mc_t *i_phase_A, uint32_t n, mc_t v_max_V, mc_ab_t *v_ab_V)
{
    const pmsm_id_config_t *c = &id->cfg;
    v_ab_V->alpha = v_ab_V->beta = MC_ZERO;
    if (id->phase == PMSM_ID_DONE || id->phase == PMSM_ID_REJECTED) {
        return false;
    }
    for (uint32_t j = 0; j < n; ++j) {
        if (mc_gt(mc_abs(i_phase_A[j]), c->i_trip_A)) {
            return pmsm_id_reject(id, "over-current");
        }
    }
    switch (id->phase) {
    case PMSM_ID_ALIGN_BETA:
        v_ab_V->beta = c->v_align_V;
        id->k += 1;
        pmsm_id_advance(id, c->align_beta_ticks, PMSM_ID_ALIGN_ALPHA);
        break;
    case PMSM_ID_ALIGN_ALPHA:
        v_ab_V->alpha = c->v_align_V;
        id->k += 1;
        pmsm_id_advance(id, c->align_alpha_ticks, PMSM_ID_REST);
        break;
    case PMSM_ID_REST:
        id->k += 1;
        pmsm_id_advance(id, c->rest_ticks, PMSM_ID_RL);
        break;
    case PMSM_ID_RL:
        v_ab_V->alpha = c->v_rl_V;
        if (rl_id_step(&id->rl, i_ab_A.alpha, c->v_rl_V, MC_ZERO)) {
            if (id->rl.state != RL_ID_DONE) {
                return pmsm_id_reject(id, "R or L implausible (outside [1/2, 2] times the model's)");
            }
            id->R_ohm = id->rl.R_ohm;
            id->L_fs_ohm = id->rl.L_fs_ohm;
            motor_model_set_rl(&id->measured, id->R_ohm, id->L_fs_ohm);
            id->phase = PMSM_ID_SPIN;
            id->k = 0;
            v_ab_V->alpha = MC_ZERO; /* the spin starts from the next sample */
        }
        break;
    case PMSM_ID_SPIN:
        if (pmsm_id_spin(id, i_ab_A, v_ab_V)) {
            /* Phi = mean |e| / w_e with w_e = theta_step fs, the speed applied */
            const mc_t phi = mc_div(id->mean_e_V, mc_mul_i(c->theta_step_rad, c->model.fs_hz));
            if (!within_factor_two(phi, c->Phi_model_Wb)) {
                return pmsm_id_reject(id, "Phi implausible (outside [1/2, 2] times the model's)");
            }
            id->Phi_Wb = phi;
            id->phase = PMSM_ID_DONE;
        }
        break;
    default:
        break;
    }
    /* limited by the bus, direction kept */
    const mc_t mag = mc_hypot(v_ab_V->alpha, v_ab_V->beta);
    if (mc_gt(mag, v_max_V)) {
        const mc_t k = mc_div(v_max_V, mag);
        v_ab_V->alpha = mc_mul(v_ab_V->alpha, k);
        v_ab_V->beta = mc_mul(v_ab_V->beta, k);
    }
    id->v_prev_V = *v_ab_V;
    id->i_prev_A = i_ab_A;
    return id->phase != PMSM_ID_DONE && id->phase != PMSM_ID_REJECTED;
}
