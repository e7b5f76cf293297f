#include "estimators/ekf_ipmsm.h"

bool ekf_ipmsm_init(ekf_ipmsm_t *e, const ekf_ipmsm_config_t *cfg, const motor_model_t *m)
{
    const ekf_ipmsm_config_t *c = cfg;
    bool ok = mc_gt(m->R_ohm, MC_ZERO) && mc_gt(m->Ld_H, MC_ZERO) && mc_gt(m->Lq_H, MC_ZERO) &&
              mc_ge(m->psi_Wb, MC_ZERO) && m->n_p >= 1 && mc_gt(m->J_kgm2, MC_ZERO) && mc_ge(m->fv_Nm_s, MC_ZERO) &&
              mc_gt(m->ts_s, MC_ZERO);
    for (int i = 0; i < EKF_N; ++i) {
        ok = ok && mc_gt(c->q[i], MC_ZERO) && mc_gt(c->p0[i], MC_ZERO);
    }
    for (int i = 0; i < EKF_M; ++i) {
        ok = ok && mc_gt(c->r[i], MC_ZERO);
    }
    e->cfg = *cfg;
    for (int i = 0; i < EKF_N; ++i) {
        e->x[i] = c->x0[i];
        for (int j = 0; j < EKF_N; ++j) {
            e->P[i][j] = (i == j) ? c->p0[i] : MC_ZERO;
        }
    }
    e->x[EKF_THETA] = mc_wrap_pi(e->x[EKF_THETA]);
    for (int i = 0; i < EKF_M; ++i) {
        e->innovation[i] = MC_ZERO;
    }
    e->spd_ok = ok;
    return ok;
}

/* dw/dt of (37): J dw/dt = 3/2 p ((Ld - Lq) i_d i_q + psi i_q) - d w - M_0   (6), (7) */
static inline mc_t ekf_dw(const motor_model_t *m, const mc_t *x)
{
    const mc_t torque = mc_mul(mc_mul_i(mc_mac(m->psi_Wb, mc_sub(m->Ld_H, m->Lq_H), x[EKF_ID]), m->n_p),
                               mc_mul(MC_C(1.5), x[EKF_IQ]));
    return mc_div(mc_sub(mc_sub(torque, mc_mul(m->fv_Nm_s, x[EKF_OMEGA])), x[EKF_M0]), m->J_kgm2);
}

#if defined(__GNUC__)
#define EKF_IN_LINE inline __attribute__((always_inline))
#else
#define EKF_IN_LINE inline
#endif

/* f(x) + B u of (37) */
static EKF_IN_LINE void ekf_f(const motor_model_t *m, const mc_t *x, mc_t u_d, mc_t u_q, mc_t *f)
{
    const mc_t w_el = mc_mul_i(x[EKF_OMEGA], m->n_p);
    /* L_d di_d/dt = u_d - R i_d + L_q p w i_q ; L_q di_q/dt = u_q - R i_q - L_d p w i_d - psi p w  (2) */
    f[EKF_ID] = mc_div(mc_add(mc_sub(u_d, mc_mul(m->R_ohm, x[EKF_ID])), mc_mul(mc_mul(m->Lq_H, w_el), x[EKF_IQ])), m->Ld_H);
    f[EKF_IQ] = mc_div(mc_sub(mc_sub(mc_sub(u_q, mc_mul(m->R_ohm, x[EKF_IQ])), mc_mul(mc_mul(m->Ld_H, w_el), x[EKF_ID])),
                              mc_mul(m->psi_Wb, w_el)),
                       m->Lq_H);
    f[EKF_THETA] = x[EKF_OMEGA];
    f[EKF_OMEGA] = ekf_dw(m, x);
    f[EKF_M0] = MC_ZERO;
}

/* dw/dt alone: the inputs u do not enter it */
mc_t ekf_ipmsm_accel(const ekf_ipmsm_t *e, const motor_model_t *m) { return ekf_dw(m, e->x); }

void ekf_ipmsm_predict(ekf_ipmsm_t *e, const motor_model_t *m, mc_t u_d_V, mc_t u_q_V)
{
    const ekf_ipmsm_config_t *c = &e->cfg;
    const mc_t ts = m->ts_s;
    const mc_t *x = e->x;
    /* A_d = I + Ts F(x+) (the Jacobian at the a posteriori estimate) */
    mc_t A[EKF_N][EKF_N];
    for (int i = 0; i < EKF_N; ++i) {
        for (int j = 0; j < EKF_N; ++j) {
            A[i][j] = (i == j) ? MC_ONE : MC_ZERO;
        }
    }
    const mc_t w_el = mc_mul_i(x[EKF_OMEGA], m->n_p);
    const mc_t k_t = mc_div(mc_mul_i(MC_C(1.5), m->n_p), m->J_kgm2); /* 3p/(2J) */
    const mc_t dL = mc_sub(m->Ld_H, m->Lq_H);
    A[EKF_ID][EKF_ID] = mc_sub(MC_ONE, mc_mul(ts, mc_div(m->R_ohm, m->Ld_H)));
    A[EKF_ID][EKF_IQ] = mc_mul(ts, mc_div(mc_mul(m->Lq_H, w_el), m->Ld_H));
    A[EKF_ID][EKF_OMEGA] = mc_mul(ts, mc_div(mc_mul_i(mc_mul(m->Lq_H, x[EKF_IQ]), m->n_p), m->Ld_H));
    A[EKF_IQ][EKF_ID] = mc_neg(mc_mul(ts, mc_div(mc_mul(m->Ld_H, w_el), m->Lq_H)));
    A[EKF_IQ][EKF_IQ] = mc_sub(MC_ONE, mc_mul(ts, mc_div(m->R_ohm, m->Lq_H)));
    A[EKF_IQ][EKF_OMEGA] =
        mc_neg(mc_mul(ts, mc_div(mc_mul_i(mc_mac(m->psi_Wb, m->Ld_H, x[EKF_ID]), m->n_p), m->Lq_H)));
    A[EKF_THETA][EKF_OMEGA] = ts;
    A[EKF_OMEGA][EKF_ID] = mc_mul(ts, mc_mul(k_t, mc_mul(dL, x[EKF_IQ])));
    A[EKF_OMEGA][EKF_IQ] = mc_mul(ts, mc_mul(k_t, mc_mac(m->psi_Wb, dL, x[EKF_ID])));
    A[EKF_OMEGA][EKF_OMEGA] = mc_sub(MC_ONE, mc_mul(ts, mc_div(m->fv_Nm_s, m->J_kgm2)));
    A[EKF_OMEGA][EKF_M0] = mc_neg(mc_div(ts, m->J_kgm2));

    /* the state: Heun's method, x- = x + Ts/2 (f(x) + f(x + Ts f(x))) */
    mc_t f1[EKF_N], xe[EKF_N], f2[EKF_N];
    ekf_f(m, x, u_d_V, u_q_V, f1);
    for (int i = 0; i < EKF_N; ++i) {
        xe[i] = mc_mac(x[i], ts, f1[i]);
    }
    ekf_f(m, xe, u_d_V, u_q_V, f2);
    const mc_t half_ts = mc_div_i(ts, 2);
    for (int i = 0; i < EKF_N; ++i) {
        e->x[i] = mc_mac(e->x[i], half_ts, mc_add(f1[i], f2[i]));
    }
    e->x[EKF_THETA] = mc_wrap_pi(e->x[EKF_THETA]);

    /* P- = A P+ A^T + Q  (39), written out over A's structural non-zeros
     * (A = I + Ts F: rows i_d, i_q: columns i_d, i_q, omega; theta: theta,
     * omega; omega: i_d, i_q, omega, M_0; M_0: M_0): 13 of 25 entries */
    mc_t AP[EKF_N][EKF_N];
    for (int j = 0; j < EKF_N; ++j) {
        const mc_t p0 = e->P[EKF_ID][j], p1 = e->P[EKF_IQ][j], p2 = e->P[EKF_THETA][j], p3 = e->P[EKF_OMEGA][j],
                   p4 = e->P[EKF_M0][j];
        AP[EKF_ID][j] = mc_mac(mc_mac(mc_mul(A[0][0], p0), A[0][1], p1), A[0][3], p3);
        AP[EKF_IQ][j] = mc_mac(mc_mac(mc_mul(A[1][0], p0), A[1][1], p1), A[1][3], p3);
        AP[EKF_THETA][j] = mc_mac(p2, A[2][3], p3);
        AP[EKF_OMEGA][j] = mc_mac(mc_mac(mc_mac(mc_mul(A[3][0], p0), A[3][1], p1), A[3][3], p3), A[3][4], p4);
        AP[EKF_M0][j] = p4;
    }
    for (int i = 0; i < EKF_N; ++i) {
        const mc_t *r = AP[i];
        mc_t v[EKF_N];
        v[EKF_ID] = mc_mac(mc_mac(mc_mul(r[0], A[0][0]), r[1], A[0][1]), r[3], A[0][3]);
        v[EKF_IQ] = mc_mac(mc_mac(mc_mul(r[0], A[1][0]), r[1], A[1][1]), r[3], A[1][3]);
        v[EKF_THETA] = mc_mac(r[2], r[3], A[2][3]);
        v[EKF_OMEGA] = mc_mac(mc_mac(mc_mac(mc_mul(r[0], A[3][0]), r[1], A[3][1]), r[3], A[3][3]), r[4], A[3][4]);
        v[EKF_M0] = r[4];
        for (int j = i; j < EKF_N; ++j) {
            const mc_t pij = (i == j) ? mc_add(v[j], c->q[i]) : v[j];
            e->P[i][j] = pij;
            e->P[j][i] = pij;
        }
    }
}

bool ekf_ipmsm_correct(ekf_ipmsm_t *e, mc_t i_d_A, mc_t i_q_A, mc_t theta_rad)
{
    const ekf_ipmsm_config_t *c = &e->cfg;
    /* S = C P- C^T + R: the top-left 3x3 of P- plus diag(r) */
    mc_t S[EKF_M][EKF_M];
    for (int i = 0; i < EKF_M; ++i) {
        for (int j = 0; j < EKF_M; ++j) {
            S[i][j] = (i == j) ? mc_add(e->P[i][j], c->r[i]) : e->P[i][j];
        }
    }
    /* Cholesky S = G G^T (lower G); false if S is not positive definite */
    mc_t G[EKF_M][EKF_M] = {{MC_ZERO}};
    for (int j = 0; j < EKF_M; ++j) {
        mc_t d = S[j][j];
        for (int k = 0; k < j; ++k) {
            d = mc_sub(d, mc_mul(G[j][k], G[j][k]));
        }
        if (!mc_gt(d, MC_ZERO)) {
            e->spd_ok = false;
            return false;
        }
        G[j][j] = mc_sqrt(d);
        for (int i = j + 1; i < EKF_M; ++i) {
            mc_t s = S[i][j];
            for (int k = 0; k < j; ++k) {
                s = mc_sub(s, mc_mul(G[i][k], G[j][k]));
            }
            G[i][j] = mc_div(s, G[j][j]);
        }
    }
    /* K = P- C^T S^-1 (40): for each row of P-'s first three columns b,
     * solve S k = b through G (forward, then backward) */
    mc_t K[EKF_N][EKF_M];
    for (int r = 0; r < EKF_N; ++r) {
        mc_t z[EKF_M];
        for (int i = 0; i < EKF_M; ++i) {
            mc_t s = e->P[r][i];
            for (int k = 0; k < i; ++k) {
                s = mc_sub(s, mc_mul(G[i][k], z[k]));
            }
            z[i] = mc_div(s, G[i][i]);
        }
        for (int i = EKF_M - 1; i >= 0; --i) {
            mc_t s = z[i];
            for (int k = i + 1; k < EKF_M; ++k) {
                s = mc_sub(s, mc_mul(G[k][i], K[r][k]));
            }
            K[r][i] = mc_div(s, G[i][i]);
        }
    }
    /* innovation (44): the angle's wrapped */
    e->innovation[0] = mc_sub(i_d_A, e->x[EKF_ID]);
    e->innovation[1] = mc_sub(i_q_A, e->x[EKF_IQ]);
    e->innovation[2] = mc_wrap_pi(mc_sub(theta_rad, e->x[EKF_THETA]));
    for (int r = 0; r < EKF_N; ++r) {
        mc_t dx = MC_ZERO;
        for (int i = 0; i < EKF_M; ++i) {
            dx = mc_mac(dx, K[r][i], e->innovation[i]);
        }
        e->x[r] = mc_add(e->x[r], dx); /* (43) */
    }
    e->x[EKF_THETA] = mc_wrap_pi(e->x[EKF_THETA]);
    /* Joseph form: P+ = (I - K C) P- (I - K C)^T + K R K^T, with C = [I 0]:
     * T = (I - K C) P- = P- - K P-[0:3, :], then P+ = T - T[:, 0:3] K^T +
     * K R K^T (upper triangle, mirrored) */
    mc_t T[EKF_N][EKF_N];
    for (int i = 0; i < EKF_N; ++i) {
        for (int j = 0; j < EKF_N; ++j) {
            mc_t s = e->P[i][j];
            for (int k = 0; k < EKF_M; ++k) {
                s = mc_sub(s, mc_mul(K[i][k], e->P[k][j]));
            }
            T[i][j] = s;
        }
    }
    for (int i = 0; i < EKF_N; ++i) {
        for (int j = i; j < EKF_N; ++j) {
            mc_t s = T[i][j];
            for (int k = 0; k < EKF_M; ++k) {
                s = mc_sub(s, mc_mul(T[i][k], K[j][k]));
                s = mc_mac(s, mc_mul(K[i][k], c->r[k]), K[j][k]);
            }
            e->P[i][j] = s;
            e->P[j][i] = s; /* symmetric by construction */
        }
    }
    return true;
}
