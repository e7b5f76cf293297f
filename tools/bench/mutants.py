#!/usr/bin/env python3
"""Mutation score of the tests: small changes to firmware/, which ones no test catches.

Copies the working tree to a scratch directory (your checkout is never
touched), configures and builds it with a host preset and checks that ctest
passes there. Then, for each mutant of MUTANTS (a sign, a dropped term, a
gain, a branch, an index, a bound, a counter: one small change to
firmware/), applies it, rebuilds and runs ctest in two stages (the unit
tests first, then the scenario, CLI and tool tests), stopping at the first
failure. A mutant is killed when a test fails, survives when every test
passes, and is invalid when it does not compile (a broken mutant, not a
kill: it is listed, counted apart and left out of the score).
Prints progress on stderr and one JSON object on stdout:

  {"mutants": N, "killed": K, "survived": S, "invalid": I, "score": K/(N-I),
   "golden": true|false, "golden_only": [ids], "survivors": [{"id", "file", "why"}],
   "results": [{"id", "file", "killed", "invalid", "by", "seconds", "golden_only"?}]}

Every survivor is either killed by a new test or listed in docs/testing.md
as equivalent, with the reason.

  --check-list     only check that every mutant still applies to the tree
                   (its text occurs exactly once); fast, run by ctest
  --coverage       list the files of firmware/ (generated code aside) and
                   how many mutants each has; exit 1 if a file with a
                   decision or a formula has none
  --only ID,...    run these mutants only
  --no-golden      leave the golden masters (GOLDEN: docs tables compared
                   digit for digit) out of the verdict; a mutant that
                   survives is then run against them alone, and those they
                   catch are listed as golden_only: caught by a printed
                   digit, not by a test that checks behaviour
  --preset P       host (default) or host-fixed
  --workdir DIR    scratch copy (default: a temporary directory, removed)
  --jobs N         ctest -j (default 2)
  --markdown JSON  print the table of docs/testing.md from the JSON of a run
  --full           run the whole ctest for every mutant (no stop at the first
                   failure) and list every test that kills it: shows which
                   mutants a single test guards (about twice as long)

Standard library only. About 20 s per mutant a unit test kills, up to
four minutes for one only a scenario catches, here (2 cores).
"""
from __future__ import annotations

import argparse
import json
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


@dataclass(frozen=True)
class Mutant:
    id: str
    file: str            # path under firmware/
    edits: tuple         # ((original, replacement), ...): each original occurs exactly once
    why: str             # what the change breaks


def m(id_: str, file: str, why: str, *edits: tuple[str, str]) -> Mutant:
    return Mutant(id_, file, tuple(edits), why)


MUTANTS = [
    # ---- back-EMF observer, paper 000 eqs. (25)-(28)
    m("emf_no_super_twisting_term", "estimators/emf_observer.c",
      "(25) without the lambda |eps|^(1/2) sgn(eps) term on both axes",
      ("mc_dot2(c->lambda_A, mc_sqrt_abs_sgn(o->err_f_A), c->l_ts, o->err_f_A)", "mc_mul(c->l_ts, o->err_f_A)"),
      ("mc_dot2(c->lambda_A, mc_sqrt_abs_sgn(o->err_g_A), c->l_ts, o->err_g_A)", "mc_mul(c->l_ts, o->err_g_A)")),
    m("emf_alpha_sign_f", "estimators/emf_observer.c", "(25) lower row, f axis: d_hat' = -alpha sgn(eps)",
      ("mc_add(o->e_f_hat_V, mc_mul_sgn(o->alpha_V_now, o->err_f_A))",
       "mc_sub(o->e_f_hat_V, mc_mul_sgn(o->alpha_V_now, o->err_f_A))")),
    m("emf_resistive_drop_sign_f", "estimators/emf_observer.c", "(23): +R i_f instead of -R i_f",
      ("mc_cross2(MC_ONE, mc_add(v_f_V, o->e_f_hat_V), m->R_ohm, i_f_A)",
       "mc_dot2(MC_ONE, mc_add(v_f_V, o->e_f_hat_V), m->R_ohm, i_f_A)")),
    m("emf_no_injection_filter_g", "estimators/emf_observer.c", "(28d) raw injection, no low-pass, g axis",
      ("o->z_g_V_s = mc_mac(o->z_g_V_s, c->lpf_coeff,", "o->z_g_V_s = mc_mac(o->z_g_V_s, MC_ONE,")),
    m("emf_one_half_turn", "estimators/emf_observer.c", "exp(Ts A_fg) with one half turn left out",
      ("mc_rot_fwd(half, xf, xg, &yf, &yg);", "yf = xf; yg = xg; (void)half;")),
    # ---- position and speed reconstruction, (29)-(32), (71)
    m("pos_jump_counter_sign", "estimators/position_estimator.c", "(71): k counts the wrong way",
      ("p->k += 1;", "p->k -= 1;")),
    m("pos_angle_negative_speed", "estimators/position_estimator.c", "(29) errata: wrong sign for w_r < 0",
      ("const mc_t x = neg ? e_g_V : mc_neg(e_g_V);", "const mc_t x = mc_neg(e_g_V);")),
    m("pos_speed_without_np", "estimators/position_estimator.c", "(31) without the 1/n_p",
      ("dw = mc_div(mc_div_i(num, p->cfg.n_p), p->e2_V2);", "dw = mc_div(num, p->e2_V2);")),
    m("pos_branch_not_chosen", "estimators/position_estimator.c", "switch: jump count not set to the nearest branch",
      ("p->k = mc_round_i(mc_div(off, p->cfg.pitch_rad));", "p->k = 0 * mc_round_i(mc_div(off, p->cfg.pitch_rad));")),
    m("pos_observable_threshold", "estimators/position_estimator.h", "observability test inverted at the boundary",
      ("p->valid = !mc_lt(p->e2_V2, p->cfg.e2_min_V2);", "p->valid = !mc_lt(p->e2_V2, mc_mul_i(p->cfg.e2_min_V2, 4));")),
    # ---- mechanical observer (33)-(37)
    m("mech_friction_sign", "estimators/mech_observer.c", "(33): +f_v w instead of -f_v w",
      ("mc_cross2(model->K_V_s, i_q_A, model->fv_Nm_s, m->omega_hat_rad_s)",
       "mc_dot2(model->K_V_s, i_q_A, model->fv_Nm_s, m->omega_hat_rad_s)")),
    m("mech_load_injection_sign", "estimators/mech_observer.c", "(35): load estimate integrates the wrong way",
      ("mc_add(m->tau_hat_Nm, mc_mul_sgn(c->alpha_Nm, e))", "mc_sub(m->tau_hat_Nm, mc_mul_sgn(c->alpha_Nm, e))")),
    m("mech_no_root_term", "estimators/mech_observer.c", "(35) without lambda |e|^(1/2) sgn(e)",
      ("mc_dot2(c->lambda_ts, mc_sqrt_abs_sgn(e), c->l_ts, e)", "mc_mul(c->l_ts, e)")),
    # ---- controllers
    m("st_no_antiwindup", "control/super_twisting.c", "integral keeps running while the voltage saturates",
      ("if (!hold_integral) {", "if (!hold_integral || mc_gt(MC_ONE, MC_ZERO)) {")),
    m("st_integral_sign", "control/super_twisting.c", "(14): du_1/dt = +alpha sgn(S)",
      ("mc_sub(st->u1, mc_mul_sgn(st->cfg.alpha_ts, S))", "mc_add(st->u1, mc_mul_sgn(st->cfg.alpha_ts, S))")),
    m("twisting_gains_swapped", "control/twisting.h", "(21): lambda_m and lambda_M swapped",
      ("const mc_t gain = away ? tw->cfg.lambda_M : tw->cfg.lambda_m;",
       "const mc_t gain = away ? tw->cfg.lambda_m : tw->cfg.lambda_M;")),
    # ---- start-up
    m("open_loop_no_back_emf", "startup/open_loop.c", "(68) without the K w term",
      ("mc_mul(m->K_V_s, omega_ref_rad_s));", "MC_ZERO);")),
    m("rl_id_no_trapezoid_correction", "startup/rl_identification.c", "L without the -R/2 trapezoid term",
      ("mc_sub(mc_mul_i(mc_div(excess, di), N), mc_div_i(R, 2))", "mc_mul_i(mc_div(excess, di), N)")),
    m("inv_id_no_settle_check", "startup/inverter_id.c",
      "a level off its target by 100 times the tolerance passes: an open phase is measured, not refused",
      ("mc_gt(off, mc_mul(INV_ID_SETTLED_TOL, target))", "mc_gt(off, mc_mul(mc_from_i(100), target))")),
    m("inverter_fit_no_knee", "design/inverter_fit.c",
      "the levels below twice the transition current kept in the fit of (1): R and V biased",
      ("!(i_A[next] > INVERTER_FIT_KNEE * i_tr)", "!(i_A[next] > 0.0 * i_tr)")),
    # ---- trajectory (70)
    m("traj_acceleration_sign", "trajectory/trajectory.c", "(70): theta_r'' with the wrong sign",
      ("out->accel_rad_s2 = mc_mul(mc_mul(mc_mul_i(x, -840), u2), s->a_scale);",
       "out->accel_rad_s2 = mc_mul(mc_mul(mc_mul_i(x, 840), u2), s->a_scale);")),
    # ---- paper 000's controller (control/fg_tracking)
    m("tracking_no_jerk_term", "control/fg_tracking.c", "(39): L di_g,r/dt without the theta_r^(3) part",
      ("mc_sub(rn->accel_rad_s2, r->accel_rad_s2)", "MC_ZERO")),
    m("tracking_load_feedforward_sign", "control/fg_tracking.c", "observed load fed forward with the wrong sign",
      ("i_g = mc_mac(i_g, c->load_ff_A_per_Nm, load_ff);", "i_g = mc_mac(i_g, mc_neg(c->load_ff_A_per_Nm), load_ff);")),
    m("tracking_no_back_emf_reference", "control/fg_tracking.c", "(38): v_g,r without K w_r",
      ("*v_gr = mc_mac(mc_add(Ldi_gr, mc_dot2(m->R_ohm, *i_gr, npLw, *i_fr)), m->K_V_s, r->omega_rad_s);",
       "*v_gr = mc_add(Ldi_gr, mc_dot2(m->R_ohm, *i_gr, npLw, *i_fr));")),
    m("tracking_start_offset_sign", "control/fg_tracking.c", "bumpless switch: current offset with the wrong sign",
      ("t->i_g_off_A = mc_sub(i_q_A, i_gr0);", "t->i_g_off_A = mc_sub(i_gr0, i_q_A);")),
    m("tracking_cross_coupling_f_sign", "control/fg_tracking.h", "(48): +n_p L mu_1 instead of -",
      ("mc_add(mc_cross2(m->R_ohm, xi_f, m->npL_ohm_s, cross_f), u_st)",
       "mc_add(mc_dot2(m->R_ohm, xi_f, m->npL_ohm_s, cross_f), u_st)")),
    m("tracking_twisting_sign", "control/fg_tracking.h", "(54): twisting output with the wrong sign",
      ("mc_mac(w_tw, mc_add(m->K_V_s, c->v_k_w_V_s), xi_w)", "mc_mac(mc_neg(w_tw), mc_add(m->K_V_s, c->v_k_w_V_s), xi_w)")),
    # ---- paper 000's estimator composition (estimators/fg_estimator)
    m("estimator_mech_observer_id", "estimators/fg_estimator.h", "mechanical observer fed i_d instead of i_q",
      ("mech_observer_step(&e->mech, m, closed ? e->pos.omega_est_rad_s : omega_r_rad_s, e->i_q_A);",
       "mech_observer_step(&e->mech, m, closed ? e->pos.omega_est_rad_s : omega_r_rad_s, e->i_d_A);")),
    m("estimator_frame_sign", "estimators/fg_estimator.h", "(44): estimated frame turned the wrong way",
      ("mc_rot_fwd(e->u_est, i_f_A, i_g_A, &e->i_d_A, &e->i_q_A);", "mc_rot_inv(e->u_est, i_f_A, i_g_A, &e->i_d_A, &e->i_q_A);")),
    m("estimator_front_full_step", "estimators/fg_estimator.h",
      "(6)-(8): the mid-sample frame turned by the whole step instead of half (both drives' front)",
      ("f->half = mc_rot_from_angle(mc_div_i(dphi, 2));", "f->half = mc_rot_from_angle(dphi);")),
    m("estimator_front_currents_mid", "estimators/fg_estimator.h",
      "(6): the measured currents turned into the mid-sample frame instead of the sampling instant's",
      ("mc_rot_fwd(rot_k, i_ab.alpha, i_ab.beta, i_f_A, i_g_A); /* eq. (6) */",
       "mc_rot_fwd(f->mid, i_ab.alpha, i_ab.beta, i_f_A, i_g_A); /* eq. (6) */")),
    # ---- supervisor
    m("sup_trip_first_phase_only", "supervisor/fault_monitor.c", "over-current trip looks at phase a only",
      ("k < n_phases && k < HAL_MAX_PHASES; ++k) {\n        const mc_t i = in->i_A[k];",
       "k < 1u && k < n_phases; ++k) {\n        const mc_t i = in->i_A[k];")),
    m("sup_limit_twice_vmax", "supervisor/supervisor.h", "voltage limited at 2 V_max",
      ("const bool sat = mc_gt(v_peak, v_max_V);", "const bool sat = mc_gt(v_peak, mc_mul_i(v_max_V, 2));")),
    m("sup_blend_sign", "supervisor/supervisor.h", "switch offset doubles the voltage step instead of removing it",
      ("s->blend_V[0] = mc_sub(s->v_prev_V[0], *v1_V);",
       "s->blend_V[0] = mc_sub(*v1_V, s->v_prev_V[0]);")),
    m("sup_no_return_to_open_loop", "supervisor/supervisor.c", "table: closed loop never falls back to open loop",
      ("{SUP_STATE_CLOSED_LOOP, SUP_EV_ESTIMATE_LOST, SUP_STATE_OPEN_LOOP},",
       "{SUP_STATE_CLOSED_LOOP, SUP_EV_ESTIMATE_LOST, SUP_STATE_CLOSED_LOOP},")),
    m("sup_first_fault_overwritten", "supervisor/supervisor.c", "a later fault overwrites the first cause",
      ("if (s->fault == DRIVE_FAULT_NONE) {", "if (s->fault == DRIVE_FAULT_NONE || f != DRIVE_FAULT_NONE) {")),
    # ---- phase adapter and model
    m("adapter_clarke_beta_sign", "adapter/phase_adapter.h", "3-phase Clarke: beta with the wrong sign",
      ("mc_sub(x[1], x[2]), PHASE_ADAPTER_INV_SQRT3", "mc_sub(x[2], x[1]), PHASE_ADAPTER_INV_SQRT3")),
    m("adapter_no_zero_sequence_a", "adapter/phase_adapter.h", "3-phase output: leg a without the min/max shift",
      ("out->v_V[0] = mc_add(a, shift);", "out->v_V[0] = a;")),
    m("model_set_rl_keeps_npL", "model/motor_model.c", "measured L not carried into n_p L",
      ("m->npL_ohm_s = mc_div_i(mc_mul_i(L_fs_ohm, m->n_p), m->fs_hz);", "(void)0;")),
    # ---- the paper-000 recipe (drives/paper000_drive)
    m("drive_never_closes_loop", "drives/paper000/paper000_drive.c", "the drive stays in open loop for the whole move",
      ("const bool want_closed = fast && observable && d->relock_hold == 0 && dwell_ok;",
       "const bool want_closed = false && fast && observable && d->relock_hold == 0 && dwell_ok;")),
    m("drive_voltage_start_of_sample", "drives/paper000/paper000_drive.c", "phase voltage at the start-of-sample angle",
      ("mc_rot_inv(rot_mid, v_f, v_g, &v_ab.alpha, &v_ab.beta);", "mc_rot_inv(rot_k, v_f, v_g, &v_ab.alpha, &v_ab.beta);")),
    m("drive_delay_observer_command", "drives/paper000/paper000_drive.c",
      "computation delay: the observer integrates the command, not the applied mean",
      ("d->v_ext_V = delay_applied_mean(c->d, v_ab, v_last);", "d->v_ext_V = delay_applied_mean(MC_ZERO, v_ab, v_last);")),
    m("drive_delay_output_mid_sample", "drives/paper000/paper000_drive.c",
      "computation delay: the output keeps the mid-sample frame",
      ("const mc_rot_t out = mc_rot_compose(c->from_next ? d->rot_next : rot_mid, delay_rot_fraction(rot_half, c->x, c->x2));",
       "const mc_rot_t out = rot_mid;\n    (void)rot_half;")),
    m("drive_delay_no_current_prediction", "control/delay_comp.h",
      "computation delay: the current prediction without its voltage term",
      ("const mc_t a = mc_mul(d_samples, ts_over_L);", "const mc_t a = mc_mul(d_samples, mc_sub(ts_over_L, ts_over_L));")),
    m("drive_frame_resync_phase", "drives/paper000/paper000_drive.c", "frame rotation recomputed one sample later in each cycle",
      ("((d->tick % P000_FRAME_RESYNC) == 0u)", "((d->tick % P000_FRAME_RESYNC) == 1u)")),
    m("drive_measured_rl_ignored", "drives/paper000/paper000_drive.c", "the standstill R/L measurement is never used",
      ("motor_model_set_rl(&d->model, d->rl_id.R_ohm, d->rl_id.L_fs_ohm);", "(void)0;")),
    # (the phase-count check and the latch of the step's prologue: the shell's, supervisor/guard.h, below)
    # ---- gain design
    m("design_discrete_constant_alpha", "design/paper000_design.c",
      "discrete design: the back-EMF observer's alpha does not follow the reference speed",
      ("alpha_slope = ST_ALPHA_OVER_PI * (K / L) * np * dw;", "alpha_slope = 0.0 * dw;")),
    m("design_discrete_no_ripple_cap", "design/paper000_design.c",
      "discrete design: the twisting gains are not capped by the sampled loop's ripple",
      ("if (discrete && !(ov->tw_lambda_M_rad_s3 > 0.0) && lam_M > ripple_cap) {",
       "if (discrete && !(ov->tw_lambda_M_rad_s3 > 0.0) && lam_M > 1e30) {")),
    m("design_twisting_no_margin", "design/paper000_design.c", "(22) met with no margin (1.0 instead of 1.2)",
      ("pick(ov->tw_lambda_m_rad_s3, TWISTING_MARGIN * C0)", "pick(ov->tw_lambda_m_rad_s3, 1.0 * C0)")),
    m("design_observer_pole", "design/paper000_design.c", "observer linear term at fs/20 instead of fs/10",
      ("pick(ov->emf_l_per_s, EMF_POLE_OVER_FS * fs)", "pick(ov->emf_l_per_s, 0.05 * fs)")),
    # ---- paper 001: gradient flux observer (12)-(14)
    m("flux_gradient_sign", "estimators/flux_observer.c", "(12): gamma eta (|eta|^2 - Phi^2), pushes |eta| away from Phi",
      ("mc_sub(o->rho2_target, o->rho2)", "mc_sub(o->rho2, o->rho2_target)")),
    m("flux_gradient_always_on", "estimators/flux_observer.c",
      "gradient term applied while switched off (no pure integrator for the circle fit)",
      ("const mc_t grad = o->gradient_on ?", "const mc_t grad = (o->gradient_on || mc_gt(MC_ONE, MC_ZERO)) ?")),
    m("flux_seed_at_phi", "estimators/flux_observer.c",
      "seeded at max(r, 1) Phi: at Phi for an IPMSM's active flux (r < 1 with i_d < 0), not at its radius",
      ("const mc_t r_fs = mc_mul(c->Phi_fs_V, radius);", "const mc_t r_fs = mc_mul(c->Phi_fs_V, mc_max(radius, MC_ONE));")),
    m("flux_no_trapezoid_alpha", "estimators/flux_observer.c", "(12), alpha axis: R i[k] instead of R (i[k-1] + i[k])/2",
      ("mc_div_i(mc_add(o->i_prev_A.alpha, i_A.alpha), 2)", "i_A.alpha")),
    # ---- resistance and flux tracking (estimators/resistance_tracker.h)
    m("rtrack_R_step_sign", "estimators/resistance_tracker.c", "dR_hat/dt = -R0^2 e_q i_q / (tau m^2): R runs away",
      ("t->acc_R_ohm = mc_clamp(mc_add(t->acc_R_ohm, mc_mul(mc_mul(e, v_r), c->R0_ohm)), r_lo, r_hi);",
       "t->acc_R_ohm = mc_clamp(mc_sub(t->acc_R_ohm, mc_mul(mc_mul(e, v_r), c->R0_ohm)), r_lo, r_hi);")),
    m("rtrack_Phi_step_sign", "estimators/resistance_tracker.c", "dPhi_hat/dt with the wrong sign: Phi runs away",
      ("t->acc_Phi = mc_clamp(mc_add(t->acc_Phi, mc_mul(e, v_e)), mc_neg(p_hi), p_hi);",
       "t->acc_Phi = mc_clamp(mc_sub(t->acc_Phi, mc_mul(e, v_e)), mc_neg(p_hi), p_hi);")),
    m("rtrack_emf_model_phi", "estimators/resistance_tracker.c", "the residual's back-EMF with Phi0, not Phi_hat",
      ("const mc_t emf = mc_mul(mc_mul(c->Phi0_fs_V, t->Phi_rel), step);", "const mc_t emf = mc_mul(c->Phi0_fs_V, step);")),
    m("flux_shift_sign_alpha", "estimators/flux_observer.c", "shift by the fitted centre: lambda_hat += Phi c on alpha",
      ("o->w_V.alpha = mc_sub(o->w_V.alpha, mc_mul(o->cfg.Phi_fs_V, c.alpha));",
       "o->w_V.alpha = mc_add(o->w_V.alpha, mc_mul(o->cfg.Phi_fs_V, c.alpha));")),
    # ---- paper 001: unwrap operator A (Appendix A)
    m("unwrap_turn_sign", "estimators/angle_unwrap.h", "Appendix A: n counts a wrap d < -pi the wrong way",
      ("u->n_turns += 1;", "u->n_turns -= 1;")),
    m("unwrap_delta_not_wrapped", "estimators/angle_unwrap.h", "Appendix A: delta keeps the -2 pi jump of atan2",
      ("d = mc_add(d, MC_TWO_PI);", "(void)0;")),
    # ---- paper 001: I&I speed and load observer (15)-(16)
    m("ii_load_sign", "estimators/speed_load_observer.c", "(15): tau_hat integrates the innovation the wrong way",
      ("o->load_Nm = mc_sub(o->load_Nm, mc_mul(c->k_load_Nm_s, nu));",
       "o->load_Nm = mc_add(o->load_Nm, mc_mul(c->k_load_Nm_s, nu));")),
    m("ii_no_torque_term", "estimators/speed_load_observer.c", "(15) without (n_p Phi/J) i^T Jm rho",
      ("mc_sub(mc_mul(c->ts_kt_over_J, i_q), mc_mul(c->ts_over_J, o->load_Nm))",
       "mc_neg(mc_mul(c->ts_over_J, o->load_Nm))")),
    m("ii_iq_swapped", "estimators/speed_load_observer.c", "i^T Jm rho with alpha and beta of the current swapped",
      ("mc_cross2(rho.c, i_A.beta, rho.s, i_A.alpha)", "mc_cross2(rho.c, i_A.alpha, rho.s, i_A.beta)")),
    # ---- paper 001: IDA-PBC (11)
    m("pbc_feedforward_sign", "control/ida_pbc.h", "i_q* = tau_hat/K_t - (J/K_t) dw_ref/dt",
      ("mc_dot2(load_hat_Nm, c->inv_Kt_A_Nm, c->J_over_Kt_A_s2, accel_ref_rad_s2)",
       "mc_cross2(load_hat_Nm, c->inv_Kt_A_Nm, c->J_over_Kt_A_s2, accel_ref_rad_s2)")),
    m("pbc_cross_term_measured_iq", "control/ida_pbc.h", "(11a): -n_p L w_hat i_q with the measured i_q, not i_q*",
      ("mc_mul(mc_mul(c->npL_ohm_s, omega_hat_rad_s), i_q_ref)", "mc_mul(mc_mul(c->npL_ohm_s, omega_hat_rad_s), i_q_A)")),
    # ---- paper 001: speed profile
    m("profile_theta_no_half", "trajectory/speed_profile.c", "theta* = theta_k + T x (w_k + dw x), without the 1/2",
      ("mc_div_i(dw, 2)", "dw")),
    m("profile_corner_late", "trajectory/speed_profile.c", "a segment starts one sample after its corner",
      ("tick >= c->t_tick[p->seg + 1u]", "tick > c->t_tick[p->seg + 1u]")),
    # ---- paper 001: circle fits of the start-up
    m("fit_kasa_no_mean_xy", "startup/flux_circle_fit.c", "Kasa fit: Cov(q_x, q_y) without the product of the means",
      ("const mc_t cxy = mc_sub(f->mxy, mc_mul(f->mx, f->my));", "const mc_t cxy = f->mxy;")),
    m("fit_origin_index_swap", "startup/flux_circle_fit.c", "through-origin fit: E(|p|^2 p_x) and E(|p|^2 p_y) swapped in c_y",
      ("c->beta = mc_div(mc_cross2(f->mxx, f->m2y, f->mxy, f->m2x), two_det);",
       "c->beta = mc_div(mc_cross2(f->mxx, f->m2x, f->mxy, f->m2y), two_det);")),
    m("fit_decim_off_by_one", "startup/flux_circle_fit.c", "a point every decim + 1 samples",
      ("if (f->phase < f->cfg.decim) {", "if (f->phase <= f->cfg.decim) {")),
    # ---- paper 002: EKF (37)-(44)
    m("ekf_jacobian_no_friction", "estimators/ekf_ipmsm.c", "(39): A_d's omega row without -Ts d/J (the friction term)",
      ("A[EKF_OMEGA][EKF_OMEGA] = mc_sub(MC_ONE, mc_mul(ts, mc_div(m->fv_Nm_s, m->J_kgm2)));",
       "A[EKF_OMEGA][EKF_OMEGA] = MC_ONE;")),
    m("ekf_jacobian_load_sign", "estimators/ekf_ipmsm.c", "(39): dw/dM_0 = +Ts/J instead of -Ts/J",
      ("A[EKF_OMEGA][EKF_M0] = mc_neg(mc_div(ts, m->J_kgm2));", "A[EKF_OMEGA][EKF_M0] = mc_div(ts, m->J_kgm2);")),
    m("ekf_jacobian_emf_sign", "estimators/ekf_ipmsm.c", "(39): di_q/dw with the wrong sign",
      ("A[EKF_IQ][EKF_OMEGA] =\n        mc_neg(mc_mul(", "A[EKF_IQ][EKF_OMEGA] =\n        (mc_mul(")),
    m("ekf_reluctance_torque_sign", "estimators/ekf_ipmsm.c", "(6): reluctance torque with (L_q - L_d)",
      ("const mc_t torque = mc_mul(mc_mul_i(mc_mac(m->psi_Wb, mc_sub(m->Ld_H, m->Lq_H), x[EKF_ID]), m->n_p),",
       "const mc_t torque = mc_mul(mc_mul_i(mc_mac(m->psi_Wb, mc_sub(m->Lq_H, m->Ld_H), x[EKF_ID]), m->n_p),")),
    m("ekf_euler_not_heun", "estimators/ekf_ipmsm.c", "prediction by Euler's method instead of Heun's",
      ("xe[i] = mc_mac(x[i], ts, f1[i]);", "xe[i] = x[i];")),
    m("ekf_cholesky_failure_unflagged", "estimators/ekf_ipmsm.c", "a failed factorisation in the correction leaves spd_ok set",
      ("            e->spd_ok = false;\n            return false;", "            return false;")),
    m("ekf_innovation_angle_unwrapped", "estimators/ekf_ipmsm.c", "(44): the angle's innovation not wrapped to (-pi, pi]",
      ("e->innovation[2] = mc_wrap_pi(mc_sub(theta_rad, e->x[EKF_THETA]));",
       "e->innovation[2] = mc_sub(theta_rad, e->x[EKF_THETA]);")),
    m("ekf_joseph_without_krk", "estimators/ekf_ipmsm.c", "Joseph form without + K R K^T",
      ("s = mc_mac(s, mc_mul(K[i][k], c->r[k]), K[j][k]);", "(void)0;")),
    # ---- paper 002: MTPA (10), (18)
    m("mtpa_limit_sign_lost", "control/mtpa.c", "current limit: a negative torque demand comes out positive",
      ("iq = neg ? mc_neg(lo) : lo;", "iq = neg ? lo : lo;")),
    m("mtpa_limit_no_abs", "control/mtpa.c", "current limit: the bisection on [0, i_q] instead of [0, |i_q|]",
      ("mc_t lo = MC_ZERO, hi = mc_abs(iq);", "mc_t lo = MC_ZERO, hi = iq;")),
    m("mtpa_root_branch", "control/mtpa.c", "(18): the other root of the quadratic (|i_d| largest)",
      ("return mc_lt(a, MC_ZERO) ? mc_mul(half, mc_sub(mc_neg(a), r)) : mc_mul(half, mc_sub(r, a));",
       "return mc_lt(a, MC_ZERO) ? mc_mul(half, mc_add(mc_neg(a), r)) : mc_mul(half, mc_sub(r, a));")),
    m("mtpa_newton_no_slope_sign", "control/mtpa.c", "Newton on (10): d i_d/d i_q without its sign for L_d < L_q",
      ("did = mc_lt(a, MC_ZERO) ? mc_neg(did) : did;", "(void)a;")),
    # ---- paper 002: SOSMC (27)-(28)
    m("sosmc_limit_positive_only", "control/sosmc.c", "limited flag on the positive side only",
      ("c->limited = mc_gt(mc_abs(M), cfg->M_max_Nm);", "c->limited = mc_gt(M, cfg->M_max_Nm);")),
    m("sosmc_windup_negative_side", "control/sosmc.c", "anti-windup: on the negative side frozen when the integrand pulls back",
      ("(mc_lt(M, MC_ZERO) && mc_lt(rate, MC_ZERO))", "(mc_lt(M, MC_ZERO) && mc_gt(rate, MC_ZERO))")),
    m("sosmc_no_compensation", "control/sosmc.c", "(27) without the estimated load M_0",
      ("        M = mc_add(M, M0_hat);", "        (void)M0_hat;")),
    m("smc_tanh_odd", "control/sosmc.c", "tanh(x) = tanh(|x|): the sign of the switching term lost",
      ("return mc_lt(x, MC_ZERO) ? mc_neg(t) : t;", "return t;")),
    # ---- paper 002: HTSMC (29)-(35)
    m("htsmc_gain_choice", "control/htsmc.c", "(35): alpha_M while s ds/dt <= 0 and alpha_m otherwise",
      ("} else if (!mc_gt(mc_mul(c->s, ds), MC_ZERO)) {", "} else if (mc_gt(mc_mul(c->s, ds), MC_ZERO)) {")),
    m("htsmc_nu_max_no_abs", "control/htsmc.c", "(35): the bound |nu| > nu_max checked on the positive side only",
      ("if (mc_gt(mc_abs(nu), cfg->nu_max)) {", "if (mc_gt(nu, cfg->nu_max)) {")),
    m("htsmc_no_s0_cap", "control/htsmc.c", "nu_2 with |s| not capped at s0",
      ("const mc_t as = mc_min(mc_abs(c->s), cfg->s0);", "const mc_t as = mc_abs(c->s);")),
    # ---- paper 002: inversion-based current control (9)
    m("ibcc_cross_coupling_sign_d", "control/ibcc.c", "(9): u_d with + L_q w i_q",
      ("ud = mc_sub(ud, mc_mul(mc_mul(m->Lq_H, w_el), i_q_A));", "ud = mc_add(ud, mc_mul(mc_mul(m->Lq_H, w_el), i_q_A));")),
    m("ibcc_no_prefilter", "control/ibcc.c", "the reference prefilter bypassed on the d axis",
      ("const mc_t step_d = mc_mul(c->ref_alpha, mc_sub(i_dd_A, s->i_dd_prev_A));",
       "const mc_t step_d = mc_sub(i_dd_A, s->i_dd_prev_A);")),
    m("ibcc_limit_q_only", "control/ibcc.c", "the bus limit scales u_d only (direction lost)",
      ("        uq = mc_mul(uq, k);\n", "")),
    # ---- paper 000: the load-angle law
    m("load_angle_slew_unbounded", "control/load_angle.c", "the fed-forward load jumps to the estimate (no slew)",
      ("c->load_Nm = mc_add(c->load_Nm, mc_clamp(mc_sub(target, c->load_Nm), mc_neg(k->load_slew_Nm), k->load_slew_Nm));",
       "c->load_Nm = target;")),
    m("load_angle_ldi_sign", "control/load_angle.c", "(38): L di_g,r/dt of the load's change with the wrong sign",
      ("mc_mul(k->L_over_KTs_V_per_Nm, mc_sub(c->load_Nm, load_prev))", "mc_mul(k->L_over_KTs_V_per_Nm, mc_sub(load_prev, c->load_Nm))")),
    m("load_angle_damping_sign", "control/load_angle.c", "speed damping with the wrong sign",
      ("i_g = mc_sub(i_g, mc_mul(k->damp_A_s_per_rad,", "i_g = mc_add(i_g, mc_mul(k->damp_A_s_per_rad,")),
    m("load_angle_ff_clamp_one_side", "control/load_angle.c", "the fed-forward load bounded above only",
      ("mc_clamp(load_est_Nm, mc_neg(k->load_ff_max_Nm), k->load_ff_max_Nm)", "mc_min(load_est_Nm, k->load_ff_max_Nm)")),
    # ---- paper 002's drive
    m("p002_stall_band_no_abs", "drives/paper002/paper002_drive.c", "stall band from w_d, not |w_d|: a false stall in reverse",
      ("mc_mac(c->stall_floor_rad_s, c->stall_tol, mc_abs(*w_d))", "mc_mac(c->stall_floor_rad_s, c->stall_tol, *w_d)")),
    m("p002_los_no_abs", "drives/paper002/paper002_drive.c", "loss of sync on a positive angle innovation only",
      ("!mc_le(mc_abs(d->ekf.innovation[2]), c->los_theta_rad)", "!mc_le(d->ekf.innovation[2], c->los_theta_rad)")),
    m("p002_output_lead_no_delay", "drives/paper002/paper002_drive.c", "output angle advanced by Ts/2 whatever the computation delay",
      ("const mc_t lead = mc_mac(half_ts, c->compute_delay, m->ts_s);", "const mc_t lead = half_ts;")),
    m("p002_delay_mean_is_command", "drives/paper002/paper002_drive.c", "with a delay, the EKF integrates the command, not the applied mean",
      ("const mc_ab_t u_mean = delay_applied_mean(c->compute_delay, u_ab, d->u_ab_prev_V);",
       "const mc_ab_t u_mean = delay_applied_mean(MC_ZERO, u_ab, d->u_ab_prev_V);")),
    m("ekf_angle_forward_only", "estimators/ekf_ipmsm.c", "(37): the angle's model turns forward whatever the speed's sign",
      ("f[EKF_THETA] = x[EKF_OMEGA];", "f[EKF_THETA] = mc_abs(x[EKF_OMEGA]);")),
    m("ibcc_emf_direction_lost", "control/ibcc.c", "(9): the coupling and back-EMF terms at |w|, not w",
      ("const mc_t w_el = mc_mul_i(w_hat_rad_s, m->n_p);", "const mc_t w_el = mc_mul_i(mc_abs(w_hat_rad_s), m->n_p);")),
    m("p002_output_lead_forward_only", "drives/paper002/paper002_drive.c", "the output angle's lead at |w|: the wrong way in reverse",
      ("mc_elec_angle(mc_mac(x[EKF_THETA], lead, x[EKF_OMEGA]), m->n_p)",
       "mc_elec_angle(mc_mac(x[EKF_THETA], lead, mc_abs(x[EKF_OMEGA])), m->n_p)")),
    m("p002_set_speed_no_abs", "drives/paper002/paper002_drive.c", "speed command: the back-EMF limit on positive speeds only",
      ("mc_gt(mc_mul(k_e, mc_abs(omega_rad_s)),", "mc_gt(mc_mul(k_e, omega_rad_s),")),
    m("p002_clear_without_fault", "drives/paper002/paper002_drive.c", "clear-faults restarts a running drive",
      ("    if (d->sup.state != SUP_STATE_FAULT) {\n        return false;\n    }\n    const paper002_config_t cfg = d->cfg;\n    return paper002_drive_init",
       "    const paper002_config_t cfg = d->cfg;\n    return paper002_drive_init")),
    # ---- loss of lock (supervisor/lock_monitor.c; issue 30)
    m("lock_no_current_term", "supervisor/lock_monitor.c", "the bound without the R-tolerance term k_cur |i|",
      ("mc_t b = mc_mac(c->floor_V, c->k_cur_ohm, i);", "mc_t b = c->floor_V;")),
    m("lock_no_speed_term", "supervisor/lock_monitor.c", "the bound without the speed term k_speed |w|",
      ("m->bound_V = mc_mac(b, c->k_speed_V_s, w);", "m->bound_V = b;")),
    m("lock_residual_signed", "supervisor/lock_monitor.c", "the residual's sign kept: |rho| above the target never trips",
      ("mc_mul(c->gPhi3_V, mc_abs(mc_sub(rho2_target, rho2)))", "mc_mul(c->gPhi3_V, mc_sub(rho2_target, rho2))")),
    m("lock_never_trips", "supervisor/lock_monitor.c", "the monitor off whatever ticks says",
      ("    if (c->ticks <= 0) {\n        return LOCK_CRIT_NONE;", "    if (c->ticks <= 0 || c->ticks > 0) {\n        return LOCK_CRIT_NONE;")),
    m("lock_design_no_flux_tolerance", "design/lock_monitor_design.c",
      "the bound without the flux tolerance: Phi +15 % at speed reads as a loss of lock",
      ("(sin(in->delta_max_rad) + sqrt((1.0 + in->eps_Phi) * (1.0 + in->eps_Phi) - 1.0))", "sin(in->delta_max_rad)")),
    m("lock_design_no_rho_max", "design/lock_monitor_design.c",
      "the floor on the unit circle: a salient motor's active flux (|rho| up to rho_max) not taken into account",
      ("in->i_max_A * in->rho_max;", "in->i_max_A;")),
    m("p002_lock_skipped", "drives/paper002/paper002_drive.c", "the sensorless variant without its loss-of-lock monitor",
      ("    if (eo->lock_checkable) {\n        const lock_criterion_t by_flux =",
       "    if (false && eo->lock_checkable) {\n        const lock_criterion_t by_flux =")),
    m("p002_hfi_no_hold", "estimators/hfi_angle.c", "the HF injection's angle hold left out (the creep under load)",
      ("    return mc_mac(omega_ref_rad_s, k, mc_wrap_pi(mc_sub(o->hold_rad, theta_hat_rad)));",
       "    (void)k;\n    return omega_ref_rad_s;")),
    m("p002_hfi_no_injection", "drives/paper002/paper002_drive.c", "the injection's voltage not added to the command",
      ("        const mc_ab_t u_out = {mc_add(u_ab.alpha, u_h.alpha), mc_add(u_ab.beta, u_h.beta)};",
       "        (void)u_h;\n        const mc_ab_t u_out = u_ab;")),
    m("p002_hfi_no_lock_check", "estimators/hfi_angle.c",
      "the injection's lock not checked before the polarity test (a start on an unlocked PLL)",
      ("            if (mc_lt(o->lock_amp, c->hfi_lock_amp_min)) {",
       "            if (false && mc_lt(o->lock_amp, c->hfi_lock_amp_min)) {")),
    m("p002_iron_linear", "drives/paper002/paper002_drive.c",
      "the iron model given but not applied: the linear L_d, L_q (the hardware-like handover loses synchronism)",
      ("    if (!iron_model_saturates(&c->iron)) {\n        return MC_ZERO;", "    if (true) {\n        return MC_ZERO;")),
    m("p002_iron_secant_on_injection", "drives/paper002/paper002_drive.c",
      "the iron's secant L on the injection too (the limit cycle under load on the biased iron)",
      ("    const mc_t w = e->model_weight ? e->model_weight(&d->est_state) : MC_ONE;",
       "    const mc_t w = MC_ONE;")),
    m("p002_iron_incremental_at_speed", "drives/paper002/paper002_drive.c",
      "the iron's incremental L at speed too (the hardware-like handover loses synchronism)",
      ("    const mc_t w = e->model_weight ? e->model_weight(&d->est_state) : MC_ONE;",
       "    const mc_t w = MC_ZERO;")),
    m("encoder_angle_mechanical", "estimators/encoder_angle.c",
      "the encoder's mechanical angle taken as the electrical frame (no pole pairs)",
      ("    return mc_rot_from_angle(mc_elec_angle(in->sample->angle_rad, o->n_p));",
       "    return mc_rot_from_angle(in->sample->angle_rad);")),
    m("flux_angle_no_turns", "estimators/flux_angle.c", "the unwrapped turns left out of the mechanical angle",
      ("    const int32_t n_mod = ((o->unwrap.n_turns % p) + p) % p;", "    const int32_t n_mod = 0;")),
    m("flux_angle_no_target", "estimators/flux_angle.c", "the active flux's radius not given to the observer (target 1)",
      ("    flux_observer_set_target(&o->flux, mc_mul(in->flux_ratio, in->flux_ratio));",
       "    flux_observer_set_target(&o->flux, MC_ONE);")),
    m("hfi_angle_blend_long_way", "estimators/hfi_angle.c",
      "the blend across +-pi the long way round (one sample's angle jumps by about pi)",
      ("mc_mac(th_h, w, mc_wrap_pi(mc_sub(th_f, th_h)))", "mc_mac(th_h, w, mc_sub(th_f, th_h))")),
    m("open_start_no_decim_check", "estimators/open_start.c",
      "a circle fit decimation of 0 accepted (the fit never takes a point)",
      ('    if (c->fit.decim < 1) return "est.fit.decim: must be >= 1";', "")),
    m("flux_speed_probe_ignores_fit", "estimators/flux_speed.c",
      "the probe's fit never trusted: the open loop starts at the reference angle, not at the rotor",
      ("    if (found || in->tick + 1u >= c->probe_ticks) {", "    if (in->tick + 1u >= c->probe_ticks) {")),
    m("flux_speed_handover_no_shift", "estimators/flux_speed.h",
      "the hand-over without the circle fit's correction of the observer's initial error",
      ("    flux_observer_shift(&o->flux, centre);\n    resistance_tracker_unprime(&o->rtrack); /* the angle jumped */\n"
       "    flux_observer_set_gradient(&o->flux, true);",
       "    resistance_tracker_unprime(&o->rtrack); /* the angle jumped */\n"
       "    flux_observer_set_gradient(&o->flux, true);")),
    m("emf_speed_omega_lim_any", "estimators/emf_speed.c",
      "a closing speed below the configured one accepted at run time",
      ("    if (mc_lt(omega_lim_rad_s, o->fs.cfg.omega_lim_rad_s)) {", "    if (false) {")),
    m("config_store_no_crc", "config/config_store.c",
      "a record taken without its CRC (a flipped bit loads)",
      ("    if (config_crc32(0, r, body) != r[body] || r[body + 1u] != CONFIG_COMMIT) {",
       "    if (r[body + 1u] != CONFIG_COMMIT) {")),
    m("params_enabled_ignored", "config/params.c",
      "a parameter of the disabled drive written while the bridge is enabled",
      ('        if (enabled) return fail(err, PARAM_ERR_NOT_WHILE_ENABLED, d->id, "only while the bridge is disabled");',
       "        (void)enabled;")),
    m("param_service_save_undesigned", "config/param_service.c",
      "parameters the design refused saved all the same (a store that cannot start the drive)",
      ("    if (!s->ready) {\n        return fail(err, PARAM_ERR_DESIGN_REFUSED",
       "    if (false) {\n        return fail(err, PARAM_ERR_DESIGN_REFUSED")),
    m("param_service_rewrite_unchanged", "config/param_service.c",
      "a stored value equal to the base's written again: the base's exact double rounded to float32",
      ("        if (now.u32 == values[k].value) continue; /* unchanged: the exact value stays */",
       "        (void)now; /* unchanged: the exact value stays */")),
    m("param_service_always_ready", "config/param_service.h",
      "the drive enabled while its parameters do not design",
      ("static inline bool param_service_ready(const param_service_t *s) { return s->ready; }",
       "static inline bool param_service_ready(const param_service_t *s) { return s != NULL; }")),
    m("design_ops_find_first", "design/ops/design_ops_registry.c",
      "the first drive's design whatever the name (the images' reference design: mcu.*_qemu)",
      ("        if (strcmp(all_designs[k]->name, name) == 0) return all_designs[k];",
       "        if (name != NULL) return all_designs[k];")),
    m("estimator_find_first", "estimators/estimator_registry.c",
      "the first estimator of the family, whatever number the configuration holds",
      ("        if (e->family == family && e->id == id &&", "        if (e->family == family &&")),
    m("iron_incremental_no_bias", "model/iron_model.c", "(I1)'s d axis without the magnet's bias",
      ("    const mc_t x_d = mc_mul(mc_mul(i_db, i_db), cfg->inv_isat2_per_A2);",
       "    (void)i_db;\n    const mc_t x_d = mc_mul(mc_mul(i_d_A, i_d_A), cfg->inv_isat2_per_A2);")),
    m("iron_no_q_weight", "model/iron_model.c", "(S2)'s u_b/u_s without L_q0/L_d0 on i_q: the q axis saturates late",
      ("mc_mac(mc_mul(i_db, i_db), cfg->lq_over_ld, mc_mul(i_q_A, i_q_A))",
       "mc_mac(mc_mul(i_db, i_db), MC_ONE, mc_mul(i_q_A, i_q_A))")),
    # ---- the HF injection and the magnet polarity test (issue 31)
    m("hfi_demod_sign", "estimators/hf_injection.c", "(H4) with the wrong sign: e = pi/2 stable",
      ("cfg->eps_gain_per_A = mc_div(MC_C(2.0),", "cfg->eps_gain_per_A = mc_div(MC_C(-2.0),")),
    m("hfi_fundamental_raw", "estimators/hf_injection.c", "(H5) replaced by the raw sample (the triangle left in)",
      ("    o->i_f_A.alpha = mc_div_i(mc_sub(mc_add(mc_mul_i(c0.alpha, 3), mc_mul_i(c1.alpha, 2)), c2.alpha), 4);",
       "    o->i_f_A.alpha = i_A.alpha;")),
    m("hfi_no_triangle_model", "estimators/hf_injection.c", "(H8) left out on alpha: the switches on and off read as glitches",
      ("o->r_A.alpha = mc_mac(o->r_A.alpha, c->ts_over_Ld_A_per_V, uh.alpha);", "o->r_A.alpha = MC_ZERO;")),
    m("hfi_no_stop_pulse", "estimators/hf_injection.c", "switched off without the stop pulse (the triangle's last peak left in the winding)",
      ("    } else if (o->stopping) {", "    } else if (o->stopping && !o->stopping) {")),
    m("hfi_pll_type1", "estimators/hf_injection.c", "(H6) without its integral: a type-1 loop lags a turning rotor",
      ("cfg->ki_per_s = mc_mul(mc_mul(wn_rad_s, wn_rad_s), ts_s);", "cfg->ki_per_s = MC_ZERO;")),
    m("hfi_no_voltage_term", "estimators/hf_injection.c", "(H3) without the fundamental voltage's change (the controller's steps read as angle)",
      ("h_q = mc_div_i(mc_mul_i(mc_sub(h_q, mc_mul(c->ts_over_Lq_A_per_V, dv_q)), o->sign), 2);",
       "h_q = mc_div_i(mc_mul_i(h_q, o->sign), 2);")),
    m("magpol_decision_swapped", "estimators/magnet_polarity.c", "the larger peak read as the wrong end",
      ("o->result = mc_gt(o->diff_A, c->margin_A) ? 1 : (mc_lt(o->diff_A, mc_neg(c->margin_A)) ? -1 : 0);",
       "o->result = mc_gt(o->diff_A, c->margin_A) ? -1 : (mc_lt(o->diff_A, mc_neg(c->margin_A)) ? 1 : 0);")),
    m("magpol_no_margin", "estimators/magnet_polarity.c", "a decision on the noise alone (margin 0)",
      ("cfg->margin_A = mc_mul(mc_mul(MAGPOL_MARGIN_SIGMAS, MAGPOL_DIFF_NOISE_PER_PHASE), sigma_i_A);",
       "cfg->margin_A = MC_ZERO;")),
    m("magpol_samples_short", "estimators/magnet_polarity.h", "the test's length without its return pulses",
      ("return 2 * (2 * cfg->n_pulse + cfg->n_rest);", "return 2 * (cfg->n_pulse + cfg->n_rest);")),
    m("p002_innov_unbounded", "drives/paper002/paper002_drive.c",
      "the sensorless variant's angle-innovation criterion with a bound a million times its variance (never trips)",
      ("d->ekf.innovation[EKF_THETA], s_theta_rad2, stall_band)", "d->ekf.innovation[EKF_THETA], mc_mul_i(s_theta_rad2, 1000000), stall_band)")),
    m("lock_innov_no_leak", "supervisor/lock_monitor.c", "the angle-innovation count never leaks (any share of samples beyond trips)",
      ("        m->innov_count -= 1;", "        m->innov_count -= 0;")),
    m("lock_innov_no_tolerance", "supervisor/lock_monitor.c", "the angle-innovation bound without the speed tolerance (w_tol Ts)^2",
      ("const mc_t tol_rad = mc_mul(mc_abs(omega_tol_rad_s), c->ts_s);",
       "const mc_t tol_rad = mc_mul(mc_mul(MC_ZERO, omega_tol_rad_s), c->ts_s);")),
    m("lock_design_innov_no_up", "design/lock_monitor_design.c", "the count's limit without its step up: a glitch of 50 / 20 samples trips",
      ("cfg->innov_limit = (int32_t)(up * glitch_n);", "cfg->innov_limit = (int32_t)glitch_n;")),
    m("p002_lock_raised_as_sync", "drives/paper002/paper002_drive.c", "a loss of lock raised as LOSS_OF_SYNC (fault 5, not 12)",
      ("guard_fault(&p002_shell, d, DRIVE_FAULT_LOSS_OF_LOCK, out)", "guard_fault(&p002_shell, d, DRIVE_FAULT_LOSS_OF_SYNC, out)")),
    # ---- the guard every drive runs under (supervisor/guard.c, .h)
    m("guard_relock_ignores_budget", "supervisor/guard.c", "RELOCK answered where the drive cannot re-lock (budget spent)",
      ("if (react == (uint8_t)FAULT_REACT_RELOCK && can_relock) {", "if (react == (uint8_t)FAULT_REACT_RELOCK && (can_relock || !can_relock)) {")),
    m("guard_report_latches", "supervisor/guard.c", "REPORT latches the fault instead of going on",
      ("    if (react == (uint8_t)FAULT_REACT_REPORT) {\n        return GUARD_GO_ON;",
       "    if (react == (uint8_t)FAULT_REACT_REPORT) {\n        supervisor_fault(sup, f);\n        return GUARD_SAFE;")),
    m("guard_latch_unrecorded", "supervisor/guard.c", "a latched fault is not counted in the flight recorder",
      ("    flight_recorder_fault(rec, f, tick);\n    supervisor_fault(sup, f);\n}", "    (void)rec;\n    (void)tick;\n    supervisor_fault(sup, f);\n}")),
    m("guard_starts_open_loop", "supervisor/guard.c", "a drive whose angle is measured starts in OPEN_LOOP",
      ("    (void)supervisor_dispatch(sup, SUP_EV_ESTIMATE_TRUSTED);\n", "")),
    m("guard_record_loses_voltage", "supervisor/guard.h", "the flight recorder keeps the currents as the voltages",
      ("        r->v_V[k] = out->v_V[k];", "        (void)out;\n        r->v_V[k] = in->i_A[k];")),
    # ---- the shell of every drive's step (supervisor/guard.h, guard.c): the
    # phase-count and latch mutants keep their ids from when each drive had
    # its own prologue
    m("drive_phase_count_unchecked", "supervisor/guard.h", "a sample of any phase count is accepted (every drive)",
      ("if (!phase_adapter_accepts(in, n_phases) ||", "if (!phase_adapter_accepts(in, in->n_phases) ||")),
    m("drive_fault_not_latched", "supervisor/guard.h",
      "the fault state is left after one sample by the drives counting the samples that ran (papers 000, 001, sensored)",
      ("if (GUARD_MEMBER(drive, g->sup, supervisor_t)->state == SUP_STATE_FAULT) {",
       "if (GUARD_MEMBER(drive, g->sup, supervisor_t)->state == SUP_STATE_FAULT && g->ticks == GUARD_TICK_EVERY) {")),
    m("p002_fault_not_latched", "supervisor/guard.h",
      "a fault is not latched by the drive counting every step (paper 002): the next sample runs again",
      ("if (GUARD_MEMBER(drive, g->sup, supervisor_t)->state == SUP_STATE_FAULT) {",
       "if (GUARD_MEMBER(drive, g->sup, supervisor_t)->state == SUP_STATE_FAULT && g->ticks == GUARD_TICK_RUN) {")),
    m("guard_accepts_unasked", "supervisor/guard.h", "the drive's own checks of a sample never asked (an encoder's angle, the bus)",
      ("(g->accepts != 0 && !g->accepts(drive, in))", "(g->accepts != 0 && false)")),
    m("guard_check_unasked", "supervisor/guard.h", "the drive's own last checks never asked (a non-finite estimate runs on)",
      ("        f = g->check(drive);\n", "")),
    m("guard_end_reacts_before_count", "supervisor/guard.h",
      "a fault of the last checks recorded at the sample's own tick by the drives counting the samples that ran",
      ("        *tick = k + 1u;\n        return f == DRIVE_FAULT_NONE ? GUARD_GO_ON : guard_fault(g, drive, f, out);",
       "        const guard_action_t r = f == DRIVE_FAULT_NONE ? GUARD_GO_ON : guard_fault(g, drive, f, out);\n"
       "        *tick = k + 1u;\n        return r;")),
    m("guard_stop_uncounted", "supervisor/guard.c", "paper 002's 0 V steps not counted (its tick counts every step)",
      ("    if (g->ticks == GUARD_TICK_EVERY) {\n        *GUARD_MEMBER", "    if (false) {\n        *GUARD_MEMBER")),
    m("guard_stop_keeps_last_voltage", "supervisor/guard.c", "a 0 V stop leaves the drive's last voltage in its telemetry",
      ("        g->stopped(drive);\n", "")),
    m("guard_relock_never_asked", "supervisor/guard.c", "RELOCK never asks the drive's re-lock: every loss latched",
      ("react == (uint8_t)FAULT_REACT_RELOCK && relock != 0 && relock(drive)",
       "react == (uint8_t)FAULT_REACT_RELOCK && relock != 0 && drive == 0")),
    # ---- paper 001's drive
    m("p001_los_speed_no_abs", "drives/paper001/paper001_drive.c", "loss-of-sync speed band from w_ref, not |w_ref|",
      ("mc_mac(c->los_speed_floor_rad_s, c->los_speed_tol, mc_abs(w_ref))", "mc_mac(c->los_speed_floor_rad_s, c->los_speed_tol, w_ref)")),
    m("p001_set_speed_no_abs", "drives/paper001/paper001_drive.c", "speed command: the back-EMF limit on positive speeds only",
      ("mc_gt(mc_mul(c->model.K_V_s, mc_abs(omega_rad_s)), mc_mul(P001_CMD_VOLTAGE_SHARE, v_phase))",
       "mc_gt(mc_mul(c->model.K_V_s, omega_rad_s), mc_mul(P001_CMD_VOLTAGE_SHARE, v_phase))")),
    # ---- CAN
    m("can_tx_queue_overfilled", "comm/can_tx.c", "a full queue takes one frame more (overwrites the oldest)",
      ("if (t->count >= CAN_TX_QUEUE) {", "if (t->count > CAN_TX_QUEUE) {")),
    m("can_tx_full_drops_newest", "comm/can_tx.c", "a full queue drops the due frame, not its oldest one",
      ("    if (t->count >= CAN_TX_QUEUE) {\n        drop_one(t);\n    }",
       "    if (t->count >= CAN_TX_QUEUE) {\n        t->dropped += 1u;\n        return;\n    }")),
    m("can_tx_replies_dropped_like_telemetry", "comm/can_tx.c",
      "a full queue drops its oldest frame, a ParamReply too: a host's request goes unanswered",
      ("while (k < t->count && t->reply[(t->head + k) & mask]) {", "while (k < t->count && false) {")),
    m("can_node_heartbeat_counts_drops", "comm/can_node.c", "the heartbeat counter advances when its frame was dropped",
      ("if (heartbeat_due && n->tx.sent != before) {", "if (heartbeat_due && n->tx.sent >= before) {")),
    m("can_link_round_negative", "comm/can_link.c", "telemetry: negative values rounded towards +inf by 0.5 (float)",
      ("int64_t r = (int64_t)(y >= 0.0f ? y + 0.5f : y - 0.5f);", "int64_t r = (int64_t)(y + 0.5f);")),
    m("can_link_enable_reserved_bits", "comm/can_link.c", "CmdEnable: a set reserved bit 1 accepted",
      ("(f->data[0] & 0xFEu) != 0u", "(f->data[0] & 0xFCu) != 0u")),
    m("can_p000_clear_while_running", "drives/paper000/paper000_ops.c", "clear-faults re-initialises a running drive",
      ("if (d->sup.state != SUP_STATE_FAULT) {", "if (false) {")),
    m("can_p002_fault_events", "drives/paper002/paper002_ops.c", "telemetry: a latched fault reported as no event",
      ("s->fault_events = (uint8_t)(d->rec.events & 0xFFu);", "s->fault_events = 0u;")),
    m("can_p002_stop_ignored", "drives/paper002/paper002_ops.c", "CmdStop acknowledged, not applied",
      ("case DRIVE_CMD_STOP: ok = paper002_drive_stop(d); break;", "case DRIVE_CMD_STOP: ok = true; break;")),
    m("can_node_refusal_accepted", "comm/can_node.c", "a command the drive refused reported as carried out",
      ("return drive_command(d, &c) == DRIVE_REFUSE_NONE ? CAN_REJECT_NONE : CAN_REJECT_MODE;",
       "(void)drive_command(d, &c);\n    return CAN_REJECT_NONE;")),
    # ---- issue 27: the fourth drive (sensored FOC) and its blocks
    m("pi_ctrl_winds_up", "control/pi_ctrl.c", "the integral grows while the output is at its limit",
      ("if (!winding) {", "if (true) {\n        (void)winding;")),
    m("enc_obs_load_sign", "estimators/encoder_observer.c", "the load estimate corrected the wrong way",
      ("o->load_Nm = mc_sub(o->load_Nm, mc_mul(c->l3_ts, eps));", "o->load_Nm = mc_add(o->load_Nm, mc_mul(c->l3_ts, eps));")),
    m("enc_obs_no_turn_count", "estimators/encoder_observer.c", "the turns are not counted at the wrap",
      ("        o->turns += 1;", "        o->turns += 0;")),
    m("sfoc_no_decoupling", "control/foc_current.c", "q axis without the back-EMF feedforward",
      ("const mc_t ff_q = mc_mul(w_e_rad_s, mc_mac(m->psi_Wb, m->Ld_H, i_d_A));", "const mc_t ff_q = MC_ZERO;")),
    m("sfoc_no_delay_lead", "drives/sensored_foc/sensored_foc_drive.c", "output turned at the sample's angle",
      ("const mc_t th_out = mc_elec_angle(mc_mac(in->angle_rad, lead_s, d->obs.omega_rad_s), c->model.n_p);",
       "const mc_t th_out = th_e;\n    (void)lead_s;")),
    m("sfoc_angle_unchecked", "drives/sensored_foc/sensored_foc_drive.c", "a sample without the encoder accepted",
      ("return in->has_angle && mc_gt(in->v_bus_V", "return mc_gt(in->v_bus_V")),
    m("sfoc_move_during_move", "drives/sensored_foc/sensored_foc_drive.c", "a move accepted during a move",
      ("    if (d->mode == SFOC_MODE_POSITION && d->tick - d->move.t0_tick < d->move.n_ticks) {\n        return false; /* a move in progress */\n    }\n    const mc_t start",
       "    const mc_t start")),
    m("sfoc_op_stop_unsupported", "drives/sensored_foc/sensored_foc_ops.c", "CmdStop refused as unsupported",
      ("    case DRIVE_CMD_STOP: ok = sensored_foc_stop(d); break;\n", "")),
    m("sfoc_design_kt", "design/sensored_foc_design.c", "K_t = n_p psi instead of 3/2 n_p psi",
      ("const double kt = 1.5 * (double)mo->n_p * psi_Wb;", "const double kt = (double)mo->n_p * psi_Wb;")),
    # ---- issue 30: the shared dead-time compensation and its design
    m("dtc_ramp_transition", "control/deadtime_comp.c",
      "the transition through zero a plain ramp x (not x/2 inside the band)",
      ("        return mc_div_i(x, 2);", "        return x;")),
    m("dtc_error_sign", "control/deadtime_comp.c", "the compensation added the wrong way (the error doubled)",
      ("        const mc_t want = mc_sub(out->v_V[k], mc_mul_i(deadtime_comp_leg_error_V(d, i_A[k], v_bus_V), legs));",
       "        const mc_t want = mc_add(out->v_V[k], mc_mul_i(deadtime_comp_leg_error_V(d, i_A[k], v_bus_V), legs));")),
    m("dtc_design_no_diode_share", "design/deadtime_comp_design.c", "the body diode's share of the period left out",
      ("        f_d = 2.0 * in->dead_time_s * in->f_pwm_Hz;", "        f_d = 0.0;")),
    # ---- issue 29: the step/dir input's shaper
    m("shaper_bucket_uncapped", "trajectory/step_shaper.c",
      "the token bucket not capped: a pause banks credit and a later burst counts no excess",
      ("    credit = credit > bucket ? bucket : credit;", "    (void)bucket;")),
    m("shaper_excess_not_counted", "trajectory/step_shaper.c", "the steps beyond the limit not counted",
      ("        s->excess_steps += (uint32_t)(n - covered);", "        (void)covered;")),
    m("shaper_backlog_sign", "trajectory/step_shaper.h", "the backlog of steps with the wrong sign",
      ("return s->count_last - s->count_moved;", "return s->count_moved - s->count_last;")),
    m("profile_design_slope_sign", "design/profile_design.c", "the profile's slopes reversed",
      ("mc_from_double((omega_rad_s[k + 1] - omega_rad_s[k]) / T)", "mc_from_double((omega_rad_s[k] - omega_rad_s[k + 1]) / T)")),
    m("delay_lead_half_sample", "control/delay_comp.h", "the output lead without the delay",
      ("return mc_mul(ts_s, mc_add(MC_C(0.5), d_samples));", "(void)d_samples;\n    return mc_mul(ts_s, MC_C(0.5));")),
    m("registry_find_prefix", "drives/registry.c", "a drive found by a prefix of its name",
      ("return a[k] == b[k];", "return b[k] == '\\0';")),
    # ---- fault set
    m("recorder_events_first_only", "supervisor/flight_recorder.c", "event count moved inside the freeze: counts the first fault only",
      ("    r->events += 1u;\n    if (!r->frozen) {\n", "    if (!r->frozen) {\n        r->events += 1u;\n")),
    m("recorder_oldest_off_by_one", "supervisor/flight_recorder.c", "ring read one record late (the oldest skipped)",
      ("const uint32_t oldest = r->n - count;", "const uint32_t oldest = r->n - count + 1u;")),
    m("fm_overrun_no_leak", "supervisor/fault_monitor.c", "overrun level never leaks: isolated overruns add up to a trip",
      ("        m->overrun_level -= 1;", "        m->overrun_level -= 0;")),
    m("fm_overrun_limit_off_by_one", "supervisor/fault_monitor.c", "overrun trip one weight late (> instead of >=)",
      ("if (m->overrun_level >= c->overrun_limit) {", "if (m->overrun_level > c->overrun_limit) {")),
    m("fm_trip_samples_off_by_one", "supervisor/fault_monitor.c", "over-current trips one sample late",
      ("if (m->oc_run + 1 >= c->i_trip_samples) {", "if (m->oc_run >= c->i_trip_samples) {")),
    m("fm_rail_positive_only", "supervisor/fault_monitor.c", "ADC rail detected on the positive rail only",
      ("at_rail = at_rail || mc_ge(a, m->rail_abs_A);", "at_rail = at_rail || mc_ge(i, m->rail_abs_A);")),
    m("fm_saturation_off_by_one", "supervisor/fault_monitor.c", "saturation trips one sample early",
      ("if (m->sat_run > m->cfg.sat_max_ticks) {", "if (m->sat_run >= m->cfg.sat_max_ticks) {")),
    m("fm_stuck_run_not_reset", "supervisor/fault_monitor.c", "the stuck-sample run is not reset by a moving sample",
      ("            m->i_last_A[k] = i;\n            m->same_run[k] = 0;", "            m->i_last_A[k] = i;")),
    m("fm_i2t_negative", "supervisor/fault_monitor.c", "I^2 t allowed below 0 (cooling banks credit)",
      ("m->i2t_A2 = mc_max(MC_ZERO, mc_mac(m->i2t_A2, excess, c->i2t_gain));", "m->i2t_A2 = mc_mac(m->i2t_A2, excess, c->i2t_gain);")),
    # ---- start-up
    m("kid_negative_speed_ignored", "startup/k_identification.c", "K identification ignores moves in the negative direction",
      ("const mc_t w = mc_abs(omega_ref_rad_s);", "const mc_t w = omega_ref_rad_s;")),
    m("kid_window_off_by_one", "startup/k_identification.c", "K computed one sample after the window",
      ("if (k->n < k->cfg.n_window) {", "if (k->n <= k->cfg.n_window) {")),
    m("kid_upper_bound", "startup/k_identification.c", "plausibility: K up to 4 K_model accepted",
      ("!mc_gt(K, mc_mul(Km, MC_C(2.0)))", "!mc_gt(K, mc_mul(Km, MC_C(4.0)))")),
    m("kid_deadband_swapped", "startup/k_identification.c", "a K within the deadband adopted, one outside kept",
      ("(differs ? K_ID_DONE : K_ID_KEPT)", "(differs ? K_ID_KEPT : K_ID_DONE)")),
    m("align_turn_back_off_by_one", "startup/align.c", "the turn back overshoots by one step",
      ("2 * c->turn_ticks - (k + 1);", "2 * c->turn_ticks - k;")),
    m("align_no_off_time", "startup/align.c", "alignment ends without the 0 V time for the current to decay",
      ("+ c->settle_ticks + c->off_ticks;", "+ c->settle_ticks;")),
    m("align_ramp_down_late", "startup/align.c", "ramp down one step late (a step at its end)",
      ("mc_ratio_i(c->ramp_ticks - (k + 1), c->ramp_ticks)", "mc_ratio_i(c->ramp_ticks - k, c->ramp_ticks)")),
    m("pmsm_id_overcurrent_no_abs", "startup/pmsm_identification.c", "identification: a negative over-current missed",
      ("if (mc_gt(mc_abs(i_phase_A[j]), c->i_trip_A)) {", "if (mc_gt(i_phase_A[j], c->i_trip_A)) {")),
    m("pmsm_id_overcurrent_first_phase", "startup/pmsm_identification.c", "identification: over-current on phase a only",
      ("for (uint32_t j = 0; j < n; ++j) {", "for (uint32_t j = 0; j < n && j < 1u; ++j) {")),
    m("pmsm_id_emf_resistive_sign", "startup/pmsm_identification.c", "paper 001 (1): e = v + R i on the alpha axis",
      ("const mc_t ea = mc_sub(mc_sub(id->v_prev_V.alpha, mc_mul(id->R_ohm, ia)),",
       "const mc_t ea = mc_sub(mc_add(id->v_prev_V.alpha, mc_mul(id->R_ohm, ia)),")),
    m("pmsm_id_limit_alpha_only", "startup/pmsm_identification.c", "the bus limit scales alpha only (direction lost)",
      ("        v_ab_V->beta = mc_mul(v_ab_V->beta, k);\n", "")),
    # ---- trajectory, math
    m("poly_slope_half", "trajectory/speed_poly.c", "dw/dt of the quintic with 15 x^2 (1-x)^2 instead of 30",
      ("const mc_t dpoly = mc_mul_i(mc_mul(x2, mc_mul(one_x, one_x)), 30);",
       "const mc_t dpoly = mc_mul_i(mc_mul(x2, mc_mul(one_x, one_x)), 15);")),
    m("poly_end_not_held", "trajectory/speed_poly.c", "after t1 the reference falls back to w0",
      ("*w_rad_s = (tick <= p->t0_tick) ? p->w0_rad_s : p->w1_rad_s;", "*w_rad_s = p->w0_rad_s;")),
    m("decay_snap_positive_only", "math/decay.h", "a negative decaying offset snapped to 0 at once",
      ("return (mc_lt(mc_abs(y), MC_DECAY_SNAP)) ? MC_ZERO : y;", "return (mc_lt(y, MC_DECAY_SNAP)) ? MC_ZERO : y;")),
    m("mean_residual_dropped", "math/mc_mean.h", "running mean: the division's remainder not carried",
      ("*res = mc_sub(t, mc_mul_i(q, n));", "*res = MC_ZERO;")),
    m("rot_compose_sign", "math/frame_fg.h", "angle sum: cos(x + y) = cos cos + sin sin",
      ("r.c = mc_cross2(x.c, y.c, x.s, y.s);", "r.c = mc_dot2(x.c, y.c, x.s, y.s);")),
    # ---- gain design of papers 001 and 002
    m("p002_design_torque_constant", "design/paper002_design.c", "K_t = p psi instead of 3/2 p psi",
      ("const double Kt = 1.5 * p * psi;", "const double Kt = 1.0 * p * psi;")),
    m("p002_design_trip_below_max", "design/paper002_design.c", "a trip current below i_max accepted",
      ("if (!(in->i_trip_A >= in->i_max_A))", "if (!(in->i_trip_A >= 0.5 * in->i_max_A))")),
    m("p001_design_torque_constant", "design/paper001_design.c", "K_t = n_p Phi whatever the phase count",
      ("const double Kt = 0.5 * (double)m->n_phases * np * Phi;", "const double Kt = np * Phi;")),
    m("motor_design_phi_is_K", "design/motor_design.h", "the one design input's Phi = K instead of K / n_p",
      ("return m->K_Nm_per_A / (double)m->n_p;", "return m->K_Nm_per_A;")),
    m("p001_design_delay_advance", "design/paper001_design.c", "output advanced by n_p Ts/2 whatever the delay",
      ("cfg->est.advance_np = mc_from_double(np * (0.5 + in->compute_delay_samples));", "cfg->est.advance_np = mc_from_double(np * 0.5);")),
    m("persist_off_by_one", "supervisor/fault_monitor.h", "a persistent condition reported one sample late",
      ("return condition && p->run >= n;", "return condition && p->run > n;")),
    m("recorder_slot_after_freeze", "supervisor/flight_recorder.h", "the ring keeps recording after the fault froze it",
      ("return r->frozen ? 0 : &r->ring[r->n & (FLIGHT_RECORDER_DEPTH - 1u)];",
       "return &r->ring[r->n & (FLIGHT_RECORDER_DEPTH - 1u)];"),
      ("    if (!r->frozen) {\n        r->n += 1u;", "    {\n        r->n += 1u;")),
    m("p001_applied_mean_without_delay", "drives/paper001/paper001_drive.h",
      "computation delay: paper 001's observers integrate the command, not the applied mean",
      ("return delay_applied_mean(c->compute_delay, v, v_prev);", "return delay_applied_mean(MC_ZERO, v, v_prev);")),
    m("delay_applied_mean_sign", "control/delay_comp.h", "computation delay: (1 + d) v - d v_prev on alpha",
      ("m.alpha = mc_mac(v.alpha, d_samples, mc_sub(v_prev.alpha, v.alpha));",
       "m.alpha = mc_mac(v.alpha, d_samples, mc_sub(v.alpha, v_prev.alpha));")),
    m("can_p001_clear_while_running", "drives/paper001/paper001_ops.c", "clear-faults re-initialises a running speed drive",
      ("if (d->sup.state != SUP_STATE_FAULT) {", "if (false) {")),
    m("emf_schedule_constant", "estimators/emf_observer.h", "scheduled injection: alpha stays at its standstill value",
      ("o->alpha_V_now = mc_mac(o->cfg.alpha_V, o->cfg.alpha_V_per_rad_s, speed_abs_rad_s);", "o->alpha_V_now = o->cfg.alpha_V;")),
    m("fixed_div_truncates", "math/mc_num_fixed.h", "Q14.17 division truncated instead of rounded (short path)",
      ("return (int32_t)(((ua << MC_FRAC_BITS) + (ub >> 1)) / ub);", "return (int32_t)((ua << MC_FRAC_BITS) / ub);")),
    m("float_wrap_pi_closed", "math/mc_num_float.h", "wrap to [-pi, pi] instead of [-pi, pi): +pi left as is",
      ("if (x >= -MC_PI && x < MC_PI) {", "if (x >= -MC_PI && x <= MC_PI) {")),
]


# Files of firmware/ with no mutant, each with the reason; every other file
# with a decision or a formula (a .c file, or a header with a function body)
# must have at least one (checked by --check-list, so by ctest).
NO_MUTANT = {
    "design/ops/drive_design_ops.c": "drive_design_defaults_input: the design's defaults then the table's, no "
                                     "decision (firmware.Params.DesignOpsDesignEachDrivesDefaults compares the "
                                     "result with each board file's design)",
    "design/ops/paper000_design_ops.c": "a design's operations: its sizes and two forwarding calls",
    "design/ops/paper001_design_ops.c": "a design's operations: its sizes and two forwarding calls",
    "design/ops/paper002_design_ops.c": "a design's operations: its sizes and two forwarding calls",
    "design/ops/sensored_foc_design_ops.c": "a design's operations: its sizes and two forwarding calls",
    "config/generated/board_params.c": "parameter tables generated by tools/params/gen_params.py from "
                                       "firmware/config/board_params.toml (ctest tools.params_current compares them)",
    "drives/paper000/generated/paper000_params.c": "parameter table generated by tools/params/gen_params.py "
                                                   "(ctest tools.params_current)",
    "drives/paper001/generated/paper001_params.c": "parameter table generated by tools/params/gen_params.py "
                                                   "(ctest tools.params_current)",
    "drives/paper002/generated/paper002_params.c": "parameter table generated by tools/params/gen_params.py "
                                                   "(ctest tools.params_current)",
    "drives/sensored_foc/generated/sensored_foc_params.c": "parameter table generated by tools/params/gen_params.py "
                                                           "(ctest tools.params_current)",
    "estimators/rotor_angle.c": "its one decision, rotor_angle_problem's n_p >= 1, is checked first by the EKF's "
                                "init in paper 002's configuration (the only drive of the family), so no test "
                                "can tell it broken; it guards a drive of the family without an EKF",
    "control/pi_ctrl.h": "pi_ctrl_reset only sets two fields (the step and init are in pi_ctrl.c, which has mutants)",
    "model/iron_model.h": "its one inline decision, iron_model_saturates (1/i_sat^2 > 0), is what the drive "
                          "branches on: p002_iron_linear takes that branch away (model/iron_model.c has mutants)",
    "drives/drive.h": "the interface: each inline function is one call through the drive's table "
                      "(every program and test that runs a drive goes through it)",
    "drives/paper001/boards/vesc6_params.c": "parameter values generated by tools/bench/pil_gen.cpp --board-params "
                           "(ctest mcu.board_params_current regenerates and compares them)",
    "drives/paper002/boards/vesc6_params.c": "parameter values generated by tools/bench/pil_gen.cpp --board-params "
                           "(ctest mcu.board_params_current regenerates and compares them)",
    "drives/paper000/boards/odrive36_params.c": "parameter values generated by tools/bench/pil_gen.cpp --board-params "
                           "(ctest mcu.board_params_current regenerates and compares them)",
    "drives/paper002/boards/vesc6_sensorless_params.c": "parameter values generated by tools/bench/pil_gen.cpp --board-params "
                           "(ctest mcu.board_params_current regenerates and compares them)",
    "comm/generated/drive_can.c": "generated by cantools from tools/can/drive.dbc (scripts/gen_can.sh); "
                                  "tools.can_contract checks it against the DBC",
    "control/twisting.c": "only instantiates the inline twisting_step of control/twisting.h (which has one)",
    "estimators/fg_estimator.c": "initialisation only; the composition's step is inline in fg_estimator.h (which has two)",
    "comm/can_tx.h": "can_tx_due forwards to can_tx_next_due of can_tx.c",
    "drives/paper000/paper000_drive.h": "its one function body is an accessor (paper000_drive_flight_recorder)",
    "estimators/flux_observer.h": "its function bodies are setters (gradient on/off, target, R, held voltage)",
    "estimators/resistance_tracker.h": "its one function body is a setter (resistance_tracker_unprime)",
    "math/mc_num.h": "chooses the backend; no function body (\"static inline\" appears in a comment)",
    "math/mc_convert.h": "host-side conversions (mc_from_double is the designs'); every design mutant goes through it",
}

# Golden masters: tests that compare printed figures digit for digit (a
# table of docs/ regenerated and diffed). They fail on any change of a
# digit, so they "kill" anything; --no-golden leaves them out of the verdict.
GOLDEN_RE = r"^docs[.]tables_"
# The unit tests (GoogleTest suites: firmware.Suite.Case, sim.Suite.Case,
# hal.Suite.Case), run first: seconds, against minutes for the scenarios.
UNIT_RE = r"^(firmware|sim|hal)[.][A-Z]"
# tools.mutants_list and tools.mutants_script check that the mutants apply
# to the tree: under a mutant they do not, by design, so they would "kill"
# every one
NOT_A_VERDICT_RE = r"^tools[.]mutants_(list|script)$"


def apply(text: str, mut: Mutant) -> str:
    for orig, repl in mut.edits:
        n = text.count(orig)
        if n != 1:
            raise ValueError(f"mutant {mut.id}: text occurs {n} times in firmware/{mut.file} (want 1): {orig!r}")
        text = text.replace(orig, repl)
    return text


def needs_mutant(path: Path) -> bool:
    """A .c file, or a header with a function body (static inline)."""
    if path.suffix == ".c":
        return True
    return path.suffix == ".h" and "static inline" in path.read_text(encoding="utf-8")


def mutant_path(src: Path, rel: str) -> Path:
    """A mutant's file: relative to firmware/, or design/... (the host-side
    design, outside firmware/ since issue 27) relative to the root."""
    return src / rel if rel.startswith("design/") else src / "firmware" / rel


def coverage(src: Path) -> tuple[dict[str, int], list[str]]:
    """Mutants per file of firmware/ and design/, and the files that need one and have none."""
    counts: dict[str, int] = {}
    for f in sorted((src / "firmware").rglob("*")):
        if f.suffix in (".c", ".h"):
            counts[f.relative_to(src / "firmware").as_posix()] = 0
    for f in sorted((src / "design").rglob("*")):
        if f.suffix in (".c", ".h"):
            counts[f.relative_to(src).as_posix()] = 0
    for mut in MUTANTS:
        counts[mut.file] = counts.get(mut.file, 0) + 1
    missing = [f for f, n in counts.items()
               if n == 0 and f not in NO_MUTANT and needs_mutant(mutant_path(src, f))]
    return counts, missing


def check_list(src: Path, out=None) -> int:
    out = out or sys.stdout
    bad = 0
    ids = set()
    for mut in MUTANTS:
        if mut.id in ids:
            print(f"mutants.py: duplicate id {mut.id}", file=sys.stderr)
            bad += 1
        ids.add(mut.id)
        path = mutant_path(src, mut.file)
        try:
            apply(path.read_text(encoding="utf-8"), mut)
        except (OSError, ValueError) as e:
            print(f"mutants.py: {e}", file=sys.stderr)
            bad += 1
    counts, missing = coverage(src)
    for f in missing:
        print(f"mutants.py: firmware/{f} has a decision or a formula and no mutant "
              f"(add one to MUTANTS, or its reason to NO_MUTANT)", file=sys.stderr)
    stale = [f for f in NO_MUTANT if f not in counts or counts[f] > 0]
    for f in stale:
        print(f"mutants.py: NO_MUTANT names firmware/{f}, which has mutants or does not exist", file=sys.stderr)
    print(json.dumps({"mutants": len(MUTANTS), "files": sum(1 for n in counts.values() if n > 0),
                      "not_applicable": bad, "files_without_mutant": missing}), file=out)
    return 1 if bad or missing or stale else 0


def print_coverage(src: Path) -> int:
    counts, missing = coverage(src)
    for f, n in counts.items():
        note = "" if n else ("  (" + NO_MUTANT[f] + ")" if f in NO_MUTANT else
                            ("  MISSING" if f in missing else "  (declarations only)"))
        print(f"{n:3d}  firmware/{f}{note}")
    print(f"{len(MUTANTS)} mutants over {sum(1 for n in counts.values() if n > 0)} files; "
          f"{len(missing)} file(s) with a decision or a formula and no mutant")
    return 1 if missing else 0


def is_scenario_check(test: str) -> bool:
    """A motorsim scenario's run or check (sim.NAME.run, sim.NAME.check, not
    the CLI error cases) or a robustness sweep: counted, not named, in the table."""
    if test.startswith("sim.robustness."):
        return True
    return test.startswith("sim.") and not test.startswith("sim.cli.") and test.endswith((".run", ".check"))


def markdown(path: Path) -> int:
    """The per-mutant table of docs/testing.md from a run's JSON."""
    try:
        text = path.read_text(encoding="utf-8")
        doc = json.loads(text)
        results = doc["results"]
    except (OSError, ValueError, KeyError) as e:
        print(f"mutants.py: --markdown: cannot read {path}: {e}", file=sys.stderr)
        return 2
    by_id = {x.id: x for x in MUTANTS}
    inv = doc.get("invalid", 0)
    gold = "" if doc.get("golden", True) else \
        f"; golden masters left out, {len(doc.get('golden_only', []))} survivor(s) caught by them alone"
    print(f"{doc['killed']} of {doc['mutants'] - inv} valid mutants killed, {doc['survived']} survived, "
          f"{inv} invalid (do not compile){gold}.\n")
    print("| mutant | file | change | killed by (tests) |")
    print("| --- | --- | --- | --- |")
    for r in results:
        mut = by_id.get(r["id"])
        killers = r.get("killed_by", [r["by"]] if r["killed"] else [])
        short = [k.replace("firmware.", "").replace("sim.", "") for k in killers]
        unit = [s for k, s in zip(killers, short) if not is_scenario_check(k)]
        scen = len(short) - len(unit)
        what = ", ".join(unit) + (f"{', ' if unit else ''}{scen} scenario checks" if scen else "")
        why = (mut.why if mut else "").replace("|", "\\|")
        if r.get("invalid"):
            verdict = "**invalid** (does not compile)"
        elif not r["killed"]:
            verdict = "**survived**" + (" (golden master only)" if r.get("golden_only") else "")
        else:
            verdict = f"{len(short)}: {what}"
        print(f"| `{r['id']}` | `{mut.file if mut else '?'}` | {why} | {verdict} |")
    return 0


def sh(cmd: list[str], cwd: Path, log: Path) -> int:
    with open(log, "w", encoding="utf-8") as f:
        return subprocess.run(cmd, cwd=cwd, stdout=f, stderr=subprocess.STDOUT).returncode


def copy_tree(dst: Path) -> None:
    files = subprocess.run(["git", "ls-files", "-co", "--exclude-standard", "-z"], cwd=ROOT, check=True,
                           capture_output=True).stdout.decode().split("\0")
    for rel in filter(None, files):
        s = ROOT / rel
        if s.is_file():
            d = dst / rel
            d.parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(s, d)


def failures(log: Path) -> list[str]:
    """Names of the failed tests in a ctest log, in the order they failed."""
    names: list[str] = []
    for line in log.read_text(encoding="utf-8", errors="replace").splitlines():
        if "***Failed" in line or "***Exception" in line or "***Timeout" in line or "***Not Run" in line:
            if "***Not Run" in line:
                continue  # fixtures whose setup failed: not a verdict of their own
            name = line.split(":", 1)[-1].split("...")[0].strip()
            if name and name not in names:
                names.append(name)
    return names


def ctest_stages(a, logs: Path, name: str, src: Path, golden: bool) -> tuple[bool, list[str], str]:
    """ctest in two stages (unit tests, then the rest), stopping at the first
    failure unless --full. Returns (failed, failed tests in order, first)."""
    base = ["ctest", "--preset", a.preset, "-j", str(a.jobs), "--timeout", "300"]
    if not a.full:
        base.append("--stop-on-failure")
    rest_excl = UNIT_RE + "|" + NOT_A_VERDICT_RE + ("" if golden else "|" + GOLDEN_RE)
    stages = [("unit", ["-R", UNIT_RE, "-E", NOT_A_VERDICT_RE]), ("rest", ["-E", rest_excl])]
    killers: list[str] = []
    failed = False
    for stage, sel in stages:
        log = logs / f"{name}.{stage}.log"
        if sh(base + sel, src, log) != 0:
            failed = True
            killers += [k for k in failures(log) if k not in killers]
            if not a.full:
                break
    first = killers[0] if killers else ("?" if failed else "")
    return failed, killers, first


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--check-list", action="store_true")
    ap.add_argument("--coverage", action="store_true")
    ap.add_argument("--only", default="")
    ap.add_argument("--no-golden", action="store_true")
    ap.add_argument("--preset", default="host", choices=["host", "host-fixed"])
    ap.add_argument("--workdir", default="")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--full", action="store_true")
    ap.add_argument("--markdown", metavar="JSON")
    a = ap.parse_args()
    if a.check_list:
        return check_list(ROOT)
    if a.coverage:
        return print_coverage(ROOT)
    if a.markdown:
        return markdown(Path(a.markdown))
    chosen = MUTANTS
    if a.only:
        want = set(a.only.split(","))
        unknown = want - {x.id for x in MUTANTS}
        if unknown:
            print(f"mutants.py: --only: unknown mutant(s) {', '.join(sorted(unknown))}", file=sys.stderr)
            return 2
        chosen = [x for x in MUTANTS if x.id in want]
    if check_list(ROOT, out=sys.stderr) != 0:
        return 2
    tmp = None
    if a.workdir:
        work = Path(a.workdir)
        shutil.rmtree(work, ignore_errors=True)
        work.mkdir(parents=True)
    else:
        tmp = tempfile.TemporaryDirectory(prefix="mc_mutants_")
        work = Path(tmp.name)
    src = work / "src"
    copy_tree(src)
    logs = work / "logs"
    logs.mkdir()
    golden = not a.no_golden
    print(f"mutants.py: building the unmutated copy in {src}", file=sys.stderr)
    # the copy has no venv of its own: the checkout's serves the python tests
    # (its folder resolved: a .venv that links elsewhere must be named by
    # its real path for the VM tests, which see the host's root file
    # system but not /tmp)
    venv_python = (ROOT / ".venv").resolve() / "bin" / "python"
    configure = ["cmake", "--preset", a.preset]
    if venv_python.exists():
        configure.append(f"-DMC_PYTHON={venv_python}")
    if sh(configure, src, logs / "configure.log") != 0 or \
            sh(["cmake", "--build", "--preset", a.preset], src, logs / "build.log") != 0:
        print(f"mutants.py: the unmutated tree does not build (see {logs})", file=sys.stderr)
        return 1
    # the unmutated tree passes every test, the golden masters included
    # (else "caught by the golden master only" would mean nothing)
    failed, _, first = ctest_stages(a, logs, "clean", src, golden=True)
    if failed:
        print(f"mutants.py: ctest fails on the unmutated tree: {first}", file=sys.stderr)
        return 1
    golden_cmd = ["ctest", "--preset", a.preset, "--timeout", "300", "-R", GOLDEN_RE]
    results = []
    for i, mut in enumerate(chosen, 1):
        path = mutant_path(src, mut.file)
        original = path.read_text(encoding="utf-8")
        t0 = time.monotonic()
        invalid = False
        golden_only = False
        killers: list[str] = []
        try:
            path.write_text(apply(original, mut), encoding="utf-8")
            if sh(["cmake", "--build", "--preset", a.preset], src, logs / f"{mut.id}.build.log") != 0:
                # does not compile: a broken mutant, not a kill
                invalid, killed, by = True, False, "build"
            else:
                killed, killers, by = ctest_stages(a, logs, mut.id, src, golden)
                if not killed and not golden:
                    golden_only = sh(golden_cmd, src, logs / f"{mut.id}.golden.log") != 0
        finally:
            path.write_text(original, encoding="utf-8")
        dt = time.monotonic() - t0
        r = {"id": mut.id, "file": "firmware/" + mut.file, "killed": killed, "invalid": invalid, "by": by,
             "seconds": round(dt, 1)}
        if not golden:
            r["golden_only"] = golden_only
        if a.full:
            r["killed_by"] = killers
        results.append(r)
        verdict = ("INVALID (does not compile)" if invalid else "killed by " + by if killed else
                   "SURVIVED" + (" (the golden master alone catches it)" if golden_only else ""))
        print(f"[{i}/{len(chosen)}] {mut.id}: {verdict} ({dt:.0f} s)", file=sys.stderr)
    # leave the copy as unmutated as it started
    sh(["cmake", "--build", "--preset", a.preset], src, logs / "build_final.log")
    killed = sum(r["killed"] for r in results)
    n_invalid = sum(r["invalid"] for r in results)
    by_id = {x.id: x for x in chosen}
    valid = len(results) - n_invalid
    out = {"mutants": len(results), "killed": killed, "survived": valid - killed, "invalid": n_invalid,
           "score": round(killed / valid, 3) if valid else None, "preset": a.preset, "golden": golden,
           "golden_only": [r["id"] for r in results if r.get("golden_only")],
           "survivors": [{"id": r["id"], "file": r["file"], "why": by_id[r["id"]].why}
                         for r in results if not r["killed"] and not r["invalid"]],
           "invalid_mutants": [r["id"] for r in results if r["invalid"]],
           "results": results}
    print(json.dumps(out, indent=1))
    if tmp is not None:
        tmp.cleanup()
    return 0


if __name__ == "__main__":
    sys.exit(main())
