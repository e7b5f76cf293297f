#include "model/motor_model.h"

void motor_model_set_rl(motor_model_t *m, mc_t R_ohm, mc_t L_fs_ohm)
{
    m->R_ohm = R_ohm;
    m->L_H = mc_div_i(L_fs_ohm, m->fs_hz);
    m->npL_ohm_s = mc_div_i(mc_mul_i(L_fs_ohm, m->n_p), m->fs_hz);
    m->ts_over_L_A_per_V = mc_div(MC_ONE, L_fs_ohm);
    m->LJ_over_KTs_V_s2 = mc_mul(L_fs_ohm, m->J_over_K_A_s2);
    m->Lfv_over_KTs_V_s = mc_mul(L_fs_ohm, m->fv_over_K_A_s);
}

void motor_model_set_K(motor_model_t *m, mc_t K_V_s)
{
    const mc_t r = mc_div(m->K_V_s, K_V_s);
    m->K_V_s = K_V_s;
    m->J_over_K_A_s2 = mc_mul(m->J_over_K_A_s2, r);
    m->fv_over_K_A_s = mc_mul(m->fv_over_K_A_s, r);
    m->LJ_over_KTs_V_s2 = mc_mul(m->LJ_over_KTs_V_s2, r);
    m->Lfv_over_KTs_V_s = mc_mul(m->Lfv_over_KTs_V_s, r);
}
