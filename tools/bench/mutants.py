#!/usr/bin/env python3
"""Mutation score of the tests: small changes to firmware/, which ones no test catches.

Copies the working tree to a scratch directory (your checkout is never
touched), configures and builds it with a host preset and checks that ctest
passes there. Then, for each mutant of MUTANTS (a sign, a dropped term, a
gain, a branch, an index: one small change to firmware/), applies it,
rebuilds and runs ctest, stopping at the first failure: a mutant is killed
when the build or any test fails, and survives when everything passes.
Prints progress on stderr and one JSON object on stdout:

  {"mutants": N, "killed": K, "survived": S, "score": K/N,
   "survivors": [{"id", "file", "why"}], "results": [{"id", "killed", "by", "seconds"}]}

Every survivor is either killed by a new test or listed in docs/testing.md
as equivalent, with the reason.

  --check-list     only check that every mutant still applies to the tree
                   (its text occurs exactly once); fast, run by ctest
  --only ID,...    run these mutants only
  --preset P       host (default) or host-fixed
  --workdir DIR    scratch copy (default: a temporary directory, removed)
  --jobs N         ctest -j (default 2)
  --markdown JSON  print the table of docs/testing.md from the JSON of a run
  --full           run the whole ctest for every mutant (no stop at the first
                   failure) and list every test that kills it: shows which
                   mutants a single test guards (about twice as long)

Standard library only. A full run takes about a minute per mutant here.
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
      ("mc_sub(in->i_A[1], in->i_A[2]), PHASE_ADAPTER_INV_SQRT3", "mc_sub(in->i_A[2], in->i_A[1]), PHASE_ADAPTER_INV_SQRT3")),
    m("adapter_no_zero_sequence_a", "adapter/phase_adapter.h", "3-phase output: leg a without the min/max shift",
      ("out->v_V[0] = mc_add(a, shift);", "out->v_V[0] = a;")),
    m("model_set_rl_keeps_npL", "model/motor_model.c", "measured L not carried into n_p L",
      ("m->npL_ohm_s = mc_div_i(mc_mul_i(L_fs_ohm, m->n_p), m->fs_hz);", "(void)0;")),
    # ---- the paper-000 recipe (drives/paper000_drive)
    m("drive_never_closes_loop", "drives/paper000_drive.c", "the drive stays in open loop for the whole move",
      ("const bool want_closed = fast && observable && d->relock_hold == 0 && dwell_ok;",
       "const bool want_closed = false && fast && observable && d->relock_hold == 0 && dwell_ok;")),
    m("drive_voltage_start_of_sample", "drives/paper000_drive.c", "phase voltage at the start-of-sample angle",
      ("mc_rot_inv(rot_mid, v_f, v_g, &v_ab.alpha, &v_ab.beta);", "mc_rot_inv(rot_k, v_f, v_g, &v_ab.alpha, &v_ab.beta);")),
    m("drive_delay_observer_command", "drives/paper000_drive.c",
      "computation delay: the observer integrates the command, not the applied mean",
      ("d->v_ext_V.alpha = mc_mac(v_ab.alpha, c->d, mc_sub(d->last.v_a_V, v_ab.alpha));", "d->v_ext_V.alpha = v_ab.alpha;"),
      ("d->v_ext_V.beta = mc_mac(v_ab.beta, c->d, mc_sub(d->last.v_b_V, v_ab.beta));", "d->v_ext_V.beta = v_ab.beta;")),
    m("drive_delay_output_mid_sample", "drives/paper000_drive.c",
      "computation delay: the output keeps the mid-sample frame",
      ("const mc_rot_t out = mc_rot_compose(c->from_next ? d->rot_next : rot_mid, drive_rot_fraction(rot_half, c->x, c->x2));",
       "const mc_rot_t out = rot_mid;\n    (void)rot_half;")),
    m("drive_delay_no_current_prediction", "drives/paper000_drive.c",
      "computation delay: the current prediction without its voltage term",
      ("const mc_t a = mc_mul(c->d, d->model.ts_over_L_A_per_V);", "const mc_t a = MC_ZERO;")),
    m("drive_frame_resync_phase", "drives/paper000_drive.c", "frame rotation recomputed one sample later in each cycle",
      ("((d->tick % DRIVE_FRAME_RESYNC) == 0u)", "((d->tick % DRIVE_FRAME_RESYNC) == 1u)")),
    m("drive_measured_rl_ignored", "drives/paper000_drive.c", "the standstill R/L measurement is never used",
      ("motor_model_set_rl(&d->model, d->rl_id.R_ohm, d->rl_id.L_fs_ohm);", "(void)0;")),
    m("drive_phase_count_unchecked", "drives/paper000_drive.c", "a sample of any phase count is accepted",
      ("if (!phase_adapter_accepts(in, (uint8_t)DRIVE_N_PHASES)) {", "if (!phase_adapter_accepts(in, in->n_phases)) {")),
    m("drive_fault_not_latched", "drives/paper000_drive.c", "the fault state is left after one sample",
      ("if (d->sup.state == SUP_STATE_FAULT) {\n        drive_zero_output(d, out);",
       "if (d->sup.state == SUP_STATE_FAULT && d->last.tick == 0u) {\n        drive_zero_output(d, out);")),
    # ---- gain design
    m("design_discrete_constant_alpha", "design/drive_design.c",
      "discrete design: the back-EMF observer's alpha does not follow the reference speed",
      ("alpha_slope = ST_ALPHA_OVER_PI * (K / L) * np * dw;", "alpha_slope = 0.0 * dw;")),
    m("design_discrete_no_ripple_cap", "design/drive_design.c",
      "discrete design: the twisting gains are not capped by the sampled loop's ripple",
      ("if (discrete && !(ov->tw_lambda_M_rad_s3 > 0.0) && lam_M > ripple_cap) {",
       "if (discrete && !(ov->tw_lambda_M_rad_s3 > 0.0) && lam_M > 1e30) {")),
    m("design_twisting_no_margin", "design/drive_design.c", "(22) met with no margin (1.0 instead of 1.2)",
      ("pick(ov->tw_lambda_m_rad_s3, TWISTING_MARGIN * C0)", "pick(ov->tw_lambda_m_rad_s3, 1.0 * C0)")),
    m("design_observer_pole", "design/drive_design.c", "observer linear term at fs/20 instead of fs/10",
      ("pick(ov->emf_l_per_s, EMF_POLE_OVER_FS * fs)", "pick(ov->emf_l_per_s, 0.05 * fs)")),
    # ---- paper 001: gradient flux observer (12)-(14)
    m("flux_gradient_sign", "estimators/flux_observer.c", "(12): gamma eta (|eta|^2 - Phi^2), pushes |eta| away from Phi",
      ("mc_sub(o->rho2_target, o->rho2)", "mc_sub(o->rho2, o->rho2_target)")),
    m("flux_gradient_always_on", "estimators/flux_observer.c",
      "gradient term applied while switched off (no pure integrator for the circle fit)",
      ("const mc_t grad = o->gradient_on ?", "const mc_t grad = (o->gradient_on || mc_gt(MC_ONE, MC_ZERO)) ?")),
    m("flux_no_trapezoid_alpha", "estimators/flux_observer.c", "(12), alpha axis: R i[k] instead of R (i[k-1] + i[k])/2",
      ("mc_div_i(mc_add(o->i_prev_A.alpha, i_A.alpha), 2)", "i_A.alpha")),
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
]


def apply(text: str, mut: Mutant) -> str:
    for orig, repl in mut.edits:
        n = text.count(orig)
        if n != 1:
            raise ValueError(f"mutant {mut.id}: text occurs {n} times in firmware/{mut.file} (want 1): {orig!r}")
        text = text.replace(orig, repl)
    return text


def check_list(src: Path, out=sys.stdout) -> int:
    bad = 0
    ids = set()
    for mut in MUTANTS:
        if mut.id in ids:
            print(f"mutants.py: duplicate id {mut.id}", file=sys.stderr)
            bad += 1
        ids.add(mut.id)
        path = src / "firmware" / mut.file
        try:
            apply(path.read_text(encoding="utf-8"), mut)
        except (OSError, ValueError) as e:
            print(f"mutants.py: {e}", file=sys.stderr)
            bad += 1
    print(json.dumps({"mutants": len(MUTANTS), "not_applicable": bad}), file=out)
    return 1 if bad else 0


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
    print(f"{doc['killed']} of {doc['mutants']} killed, {doc['survived']} survived.\n")
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
        print(f"| `{r['id']}` | `{mut.file if mut else '?'}` | {why} | "
              f"{'**survived**' if not r['killed'] else f'{len(short)}: {what}'} |")
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


def first_failure(log: Path) -> str:
    f = failures(log)
    if f:
        return f[0]
    return "build" if "error" in log.read_text(encoding="utf-8", errors="replace") else "?"


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--check-list", action="store_true")
    ap.add_argument("--only", default="")
    ap.add_argument("--preset", default="host", choices=["host", "host-fixed"])
    ap.add_argument("--workdir", default="")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--full", action="store_true")
    ap.add_argument("--markdown", metavar="JSON")
    a = ap.parse_args()
    if a.check_list:
        return check_list(ROOT)
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
    # tools.mutants_list checks that the mutants apply to the tree: under a
    # mutant they do not, by design, so it would "kill" every one
    ctest = ["ctest", "--preset", a.preset, "-j", str(a.jobs), "--timeout", "300", "-E", "^tools[.]mutants_list$"]
    if not a.full:
        ctest.append("--stop-on-failure")
    print(f"mutants.py: building the unmutated copy in {src}", file=sys.stderr)
    # the copy has no venv of its own: the checkout's serves the python tests
    venv_python = ROOT / ".venv" / "bin" / "python"
    configure = ["cmake", "--preset", a.preset]
    if venv_python.exists():
        configure.append(f"-DMC_PYTHON={venv_python}")
    if sh(configure, src, logs / "configure.log") != 0 or \
            sh(["cmake", "--build", "--preset", a.preset], src, logs / "build.log") != 0:
        print(f"mutants.py: the unmutated tree does not build (see {logs})", file=sys.stderr)
        return 1
    if sh(ctest, src, logs / "ctest_clean.log") != 0:
        print(f"mutants.py: ctest fails on the unmutated tree: {first_failure(logs / 'ctest_clean.log')}",
              file=sys.stderr)
        return 1
    results = []
    for i, mut in enumerate(chosen, 1):
        path = src / "firmware" / mut.file
        original = path.read_text(encoding="utf-8")
        t0 = time.monotonic()
        try:
            path.write_text(apply(original, mut), encoding="utf-8")
            log = logs / f"{mut.id}.log"
            killers: list[str] = []
            if sh(["cmake", "--build", "--preset", a.preset], src, log) != 0:
                killed, by = True, "build"
            else:
                killed = sh(ctest, src, log) != 0
                by = first_failure(log) if killed else ""
                killers = failures(log) if killed else []
        finally:
            path.write_text(original, encoding="utf-8")
        dt = time.monotonic() - t0
        r = {"id": mut.id, "killed": killed, "by": by, "seconds": round(dt, 1)}
        if a.full:
            r["killed_by"] = killers
        results.append(r)
        print(f"[{i}/{len(chosen)}] {mut.id}: {'killed by ' + by if killed else 'SURVIVED'} ({dt:.0f} s)",
              file=sys.stderr)
    # leave the copy as unmutated as it started
    sh(["cmake", "--build", "--preset", a.preset], src, logs / "build_final.log")
    killed = sum(r["killed"] for r in results)
    by_id = {x.id: x for x in chosen}
    out = {"mutants": len(results), "killed": killed, "survived": len(results) - killed,
           "score": round(killed / len(results), 3) if results else None, "preset": a.preset,
           "survivors": [{"id": r["id"], "file": "firmware/" + by_id[r["id"]].file, "why": by_id[r["id"]].why}
                         for r in results if not r["killed"]],
           "results": results}
    print(json.dumps(out, indent=1))
    if tmp is not None:
        tmp.cleanup()
    return 0


if __name__ == "__main__":
    sys.exit(main())
