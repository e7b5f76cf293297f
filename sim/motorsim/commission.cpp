#include "motorsim/commission.h"

#include <cstring>
#include <stdexcept>

#include "hal_sw_plant.h"
#include "scenario/design_input.h"
#include "scenario/rig.h"
#include "scenario/rig_hal.h"

extern "C" {
#include "adapter/phase_adapter.h"
#include "control/deadtime_comp.h"
#include "hal/hal.h"
#include "math/mc_convert.h"
#include "startup/pmsm_identification.h"
}

namespace mcsim {
namespace {

struct Ctx {
    pmsm_id_t id;
    uint8_t n_phases;
    deadtime_comp_t dtc;  // the board's inverter, as the drive's ([inverter]; disabled: none)
};

void commission_callback(void* vctx, const hal_sample_t* in, hal_command_t* out)
{
    Ctx* ctx = static_cast<Ctx*>(vctx);
    mc_t i_zero;
    const mc_ab_t i_ab = phase_adapter_currents(in, &i_zero);
    // a leg swings +-v_bus/2 about the midpoint (three phases), an H-bridge +-v_bus
    const mc_t v_max = (ctx->n_phases == 3u) ? mc_div_i(in->v_bus_V, 2) : in->v_bus_V;
    mc_ab_t v_ab;
    (void)pmsm_id_step(&ctx->id, i_ab, in->i_A, in->n_phases, v_max, &v_ab);
    phase_adapter_voltages(ctx->n_phases, v_ab, out);
    // the identification integrates the voltage it intended: the inverter's
    // expected error is compensated as in the drive (its standstill R
    // would otherwise include the dead time's V_dc t f_pwm / i)
    if (ctx->dtc.cfg.enabled) {
        (void)deadtime_comp_step(&ctx->dtc, in->i_A, in->v_bus_V, out);
    }
}

}  // namespace

CommissionResult commission_pmsm(const Scenario& sc, const pmsm_id_config_t& cfg, double duration_s)
{
    Ctx ctx{};
    CommissionResult r;
    if (!pmsm_id_init(&ctx.id, &cfg)) {
        r.why = std::string("configuration rejected: ") + ctx.id.why;
        return r;
    }
    ctx.n_phases = static_cast<uint8_t>(sc.motor.n_phases());
    const deadtime_comp_config_t dtc = deadtime_comp_config(sc);
    (void)deadtime_comp_init(&ctx.dtc, &dtc);  // the design's coefficients are >= 0
    Scenario unloaded = sc;                    // commissioning runs without the run's load
    unloaded.load.clear();
    Rig rig(unloaded);
    attach_rig(rig, unloaded);  // the same bench as the run's, its board included
    if (!hal_start(&commission_callback, &ctx)) {
        hal_sw_plant_detach();
        throw std::runtime_error(std::string("hal_start: ") + hal_last_error());
    }
    // the nominal length and 1 s more for the ramp-down
    const auto limit = static_cast<std::uint32_t>((duration_s + 1.0) / sc.ts_s);
    std::uint32_t n = 0;
    while (n < limit && ctx.id.phase != PMSM_ID_DONE && ctx.id.phase != PMSM_ID_REJECTED) {
        hal_sw_plant_run(1);
        ++n;
    }
    hal_safe_state();
    hal_sw_plant_detach();
    r.duration_s = n * sc.ts_s;
    if (ctx.id.phase != PMSM_ID_DONE) {
        r.why = ctx.id.phase == PMSM_ID_REJECTED ? ctx.id.why : "did not finish in time";
        return r;
    }
    r.ok = true;
    r.R_ohm = mc_to_double(ctx.id.R_ohm);
    r.L_H = mc_to_double(ctx.id.L_fs_ohm) * sc.ts_s;
    r.Phi_Wb = mc_to_double(ctx.id.Phi_Wb);
    return r;
}

void commission_drive(const HostDrive& host, Scenario* sc, MetricList* metrics)
{
    pmsm_id_config_t cfg;
    double duration_s = 0.0;
    if (host.pmsm_identification == nullptr || !host.pmsm_identification(*sc, &cfg, &duration_s)) {
        return;
    }
    const CommissionResult c = commission_pmsm(*sc, cfg, duration_s);
    if (!c.ok) {
        throw std::runtime_error(sc->path + ": identification failed after " + std::to_string(c.duration_s) +
                                 " s: " + c.why);
    }
    sc->drive_model.R_ohm = c.R_ohm;
    sc->drive_model.L_H = c.L_H;
    sc->drive_model.L_q_H = c.L_H;
    sc->drive_model.K_Nm_per_A = c.Phi_Wb * static_cast<double>(sc->drive_model.n_p);
    metrics->emplace_back("id_R_ohm", c.R_ohm);
    metrics->emplace_back("id_L_H", c.L_H);
    metrics->emplace_back("id_Phi_Wb", c.Phi_Wb);
    metrics->emplace_back("id_R_err_pct", 100.0 * (c.R_ohm / sc->motor.R_ohm - 1.0));
    metrics->emplace_back("id_L_err_pct", 100.0 * (c.L_H / sc->motor.L_H - 1.0));
    metrics->emplace_back("id_Phi_err_pct", 100.0 * (c.Phi_Wb / sc->motor.Phi_Wb() - 1.0));
    metrics->emplace_back("id_time_s", c.duration_s);
}

}  // namespace mcsim
