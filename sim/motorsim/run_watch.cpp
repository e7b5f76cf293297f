#include "motorsim/run_watch.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace mcsim {
namespace {

// The envelope is generous on purpose: it flags integrations that have left
// physics, not drives that perform badly. A winding fed by at most V (the
// bus or the amplifier's limit) carries at most V/R in steady state, and
// at most V/R plus the back-EMF's share while turning; 4 V/R + 4 i_trip
// covers both with room. The rotor of a motor driven by V turns at most at
// the no-load speed V/K_e; an external load can push it further, so the
// bound is 10 V/K_e + 100 rad/s.
constexpr double kCurrentEnvelopeOverVR = 4.0;
constexpr double kCurrentEnvelopeOverTrip = 4.0;
constexpr double kSpeedEnvelopeOverNoLoad = 10.0;
constexpr double kSpeedEnvelopeFloor_rad_s = 100.0;

std::string describe(const char* what, double x, double bound, const char* unit)
{
    char b[160];
    if (!std::isfinite(x)) {
        std::snprintf(b, sizeof b, "%s is %s", what, std::isnan(x) ? "NaN" : "infinite");
    } else {
        std::snprintf(b, sizeof b, "|%s| = %.4g %s beyond the physical bound %.4g %s", what, std::fabs(x), unit,
                      bound, unit);
    }
    return b;
}

}  // namespace

RunWatch::RunWatch(const Scenario& sc)
{
    const MotorParams& m = sc.motor;
    const double v = sc.v_max_V;  // per winding (two phases) or per leg about the midpoint (three)
    const double r = std::max(m.R_ohm, 1e-6);
    i_env_ = kCurrentEnvelopeOverVR * v / r + kCurrentEnvelopeOverTrip * sc.i_trip_A;
    const double ke = std::max(m.K_Nm_per_A, 1e-9);
    w_env_ = kSpeedEnvelopeOverNoLoad * v / ke + kSpeedEnvelopeFloor_rad_s;
}

void RunWatch::on_period(const hal_sw_plant_period_t& p, std::int64_t fault, const PmPlant& plant)
{
    if (fault != 0 && fault_ == 0) {
        fault_ = fault;
        fault_t_ = p.t_s;
        fault_i_ = std::max({std::fabs(p.i_a_meas_A), std::fabs(p.i_b_meas_A), std::fabs(p.i_c_meas_A)});
    }
    if (!diverged_what_.empty()) {
        return;
    }
    const PmPlant::State& x = plant.state();
    const struct Item {
        const char* name;
        double x, bound;
        const char* unit;
    } items[] = {{"i_a_A", x[PmPlant::kIa], i_env_, "A"},
                 {"i_b_A", x[PmPlant::kIb], i_env_, "A"},
                 {"omega_rad_s", x[PmPlant::kOmega], w_env_, "rad/s"},
                 {"theta_rad", x[PmPlant::kTheta], HUGE_VAL, "rad"}};
    for (const Item& it : items) {
        if (!std::isfinite(it.x) || std::fabs(it.x) > it.bound) {
            diverged_t_ = p.t_s;
            diverged_what_ = describe(it.name, it.x, it.bound, it.unit);
            return;
        }
    }
}

}  // namespace mcsim
