#include "model/fault_injection.h"

#include <cmath>
#include <limits>

#include "model/current_sensor.h"

namespace mcsim {

namespace {
// The sample at t_s (sampling instants are k Ts apart) is the first at or
// after `from`: half a sample of tolerance against rounding of k Ts.
bool at_or_after(double t_s, double from_s, double ts_s) { return from_s >= 0.0 && t_s >= from_s - 0.5 * ts_s; }
bool within(double t_s, double from_s, double dur_s, double ts_s)
{
    return at_or_after(t_s, from_s, ts_s) && t_s < from_s + dur_s - 0.5 * ts_s;
}
}  // namespace

void FaultInjector::analog(double t_s, double ts_s, int n, double* i)
{
    if (at_or_after(t_s, f_.gain_t_s, ts_s)) {
        for (int k = 0; k < n; ++k) i[k] *= f_.gain[k];
    }
    if (at_or_after(t_s, f_.offset_t_s, ts_s)) {
        for (int k = 0; k < n; ++k) i[k] += f_.offset_A[k];
    }
    if (within(t_s, f_.burst_t_s, f_.burst_duration_s, ts_s)) {
        for (int k = 0; k < n; ++k) {
            // Box-Muller on the burst's own stream
            const double u1 = 1.0 - uniform01(rng_), u2 = uniform01(rng_);
            i[k] += f_.burst_noise_A * std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
        }
    }
}

void FaultInjector::digital(double t_s, double ts_s, int n, double* i)
{
    if (f_.stuck_phase >= 0 && f_.stuck_phase < n && at_or_after(t_s, f_.stuck_t_s, ts_s)) {
        if (!stuck_held_) {
            stuck_held_ = true;
            stuck_value_A_ = i[f_.stuck_phase];
        }
        i[f_.stuck_phase] = stuck_value_A_;
    }
    if (within(t_s, f_.nan_t_s, ts_s, ts_s)) {
        i[0] = std::numeric_limits<double>::quiet_NaN();
    }
}

double FaultInjector::v_max_V(double t_s, double nominal_V) const
{
    return within(t_s, f_.sag_t_s, f_.sag_duration_s, 1e-12) ? f_.sag_v_max_V : nominal_V;
}

bool FaultInjector::overrun(double t_s, double ts_s) const
{
    return within(t_s, f_.overrun_t_s, f_.overrun_count * ts_s, ts_s);
}

bool FaultInjector::rotor_locked(double t_s, double ts_s) const { return at_or_after(t_s, f_.locked_rotor_t_s, ts_s); }

int FaultInjector::open_phase(double t_s, double ts_s) const
{
    return at_or_after(t_s, f_.open_phase_t_s, ts_s) ? f_.open_phase : -1;
}

}  // namespace mcsim
