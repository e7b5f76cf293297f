// rig.h - the simulated bench of a scenario: plant at its initial state,
// current sensor and amplifier (or the MCU board's inverter), as motorsim
// and the PIL recorder attach them to the software-plant HAL backend. One
// place that turns a scenario into hardware models, so the tools cannot
// disagree on it.
#ifndef MCSIM_SCENARIO_RIG_H
#define MCSIM_SCENARIO_RIG_H

#include <optional>

#include "model/amplifier.h"
#include "model/current_sensor.h"
#include "model/inverter.h"
#include "model/load_profile.h"
#include "model/pm_plant.h"
#include "model/saturation.h"
#include "model/thermal.h"
#include "scenario/scenario.h"

namespace mcsim {

struct Rig {
    explicit Rig(const Scenario& sc)
        : plant(plant_motor(sc.motor), LoadProfile(sc.load), sc.substeps), sensor(sc.sensor, sc.seed)
    {
        // The motor file's hardware effects (issue 30, docs/plant.md),
        // each absent by default (the plant's equations then as before):
        // saturation first, so the thermal model's Phi(T0) reaches it
        if (sc.motor.i_sat_A > 0.0) {
            SaturationParams s;
            s.i_sat_A = sc.motor.i_sat_A;
            s.i_bias_A = sc.motor.i_sat_bias_A;
            plant.set_saturation(s);
        }
        const ThermalParams th = thermal_params(sc.motor);
        if (th.enabled()) {
            plant.set_thermal(th);
        }
        PmPlant::State x0 = PmPlant::State::Zero();
        x0[PmPlant::kTheta] = sc.theta0_rad;
        x0[PmPlant::kOmega] = sc.omega0_rad_s;  // the rotor's speed at the start (0 unless the scenario says)
        plant.reset(x0, sc.t_start_s());  // t = 0 is the move command, after pre_ticks
        amp.v_max_V = sc.v_max_V;
        if (sc.inverter_given) {
            inverter.emplace(sc.inverter);
        }
    }
    // The motor file's thermal keys as the plant's thermal model.
    static ThermalParams thermal_params(const MotorParams& m)
    {
        ThermalParams th;
        th.R_th_K_per_W = m.R_th_K_per_W;
        th.C_th_J_per_K = m.C_th_J_per_K;
        th.T_ambient_C = m.T_ambient_C;
        th.T0_C = m.T0_C;
        th.alpha_cu_per_K = m.alpha_cu_per_K;
        th.beta_pm_per_K = m.beta_pm_per_K;
        return th;
    }
    // The plant's motor: as given, or, with a starting temperature T0_C
    // other than 20 C and no thermal model, R and Phi at T0 held ((T2),
    // (T3) of model/thermal.h); with a thermal model set_thermal does it.
    static MotorParams plant_motor(const MotorParams& m)
    {
        MotorParams p = m;
        if (m.T0_C != ThermalModel::kTref_C && !thermal_params(m).enabled()) {
            const double dT = m.T0_C - ThermalModel::kTref_C;
            p.R_ohm = m.R_ohm * (1.0 + m.alpha_cu_per_K * dT);
            p.K_Nm_per_A = m.K_Nm_per_A * (1.0 + m.beta_pm_per_K * dT);
        }
        return p;
    }
    // The inverter for hal_sw_plant_set_inverter(), or nullptr (the amplifier).
    const Inverter* inverter_or_null() const { return inverter ? &*inverter : nullptr; }
    PmPlant plant;
    CurrentSensor sensor;
    Amplifier amp;
    std::optional<Inverter> inverter;  // [inverter], or none
};

}  // namespace mcsim

#endif  // MCSIM_SCENARIO_RIG_H
