// fault_injection.h - faults the simulator injects into the rig ([faults] of
// a scenario, sim/scenarios/README.md): a locked rotor, an open winding,
// current-sensor offset and gain errors, a burst of sensor noise, samples
// that stop changing, a NaN sample, a sag of the supply and control-step
// overruns reported by the backend. The software-plant HAL backend applies
// them between the plant, the sensor and the drive, so the drive sees them
// as it would on a bench. Each is off unless its start time is >= 0.
#ifndef MCSIM_MODEL_FAULT_INJECTION_H
#define MCSIM_MODEL_FAULT_INJECTION_H

#include <cstdint>
#include <random>

namespace mcsim {

struct FaultInjection {
    double locked_rotor_t_s = -1.0;  // the rotor is held at its angle from then on
    int open_phase = -1;             // this winding (0 = a, 1 = b; stepper2) opens ...
    double open_phase_t_s = -1.0;    // ... at this time: no current flows in it
    double offset_t_s = -1.0;        // from then, each measured phase gets offset_A added
    double offset_A[3] = {0.0, 0.0, 0.0};
    double gain_t_s = -1.0;          // from then, each measured phase is scaled by gain
    double gain[3] = {1.0, 1.0, 1.0};
    double burst_t_s = -1.0;         // Gaussian noise of burst_noise_A (sigma) added ...
    double burst_duration_s = 0.0;   // ... for this long
    double burst_noise_A = 0.0;
    int stuck_phase = -1;            // this phase's sample freezes ...
    double stuck_t_s = -1.0;         // ... at its value of this time
    double nan_t_s = -1.0;           // one NaN sample of phase a at this time
    double sag_t_s = -1.0;           // the supply drops to sag_v_max_V ...
    double sag_duration_s = 0.0;     // ... for this long (the amplifier clamps to it)
    double sag_v_max_V = 0.0;
    double overrun_t_s = -1.0;       // the backend flags HAL_STATUS_OVERRUN ...
    int overrun_count = 0;           // ... on this many consecutive samples

    bool any() const
    {
        return locked_rotor_t_s >= 0.0 || open_phase_t_s >= 0.0 || offset_t_s >= 0.0 || gain_t_s >= 0.0 ||
               burst_t_s >= 0.0 || stuck_t_s >= 0.0 || nan_t_s >= 0.0 || sag_t_s >= 0.0 || overrun_t_s >= 0.0;
    }
};

// The per-run state of the injection (the frozen sample, the burst's own
// random stream, so the sensor's noise sequence is the same with or
// without a burst).
class FaultInjector {
public:
    FaultInjector(const FaultInjection& f, std::uint64_t seed) : f_(f), rng_(seed ^ 0x5eed0fa17ULL) {}
    const FaultInjection& spec() const { return f_; }

    // The sensor's input at t (n phases; gain, offset and noise burst act
    // on the analog signal, before the sensor's own noise and the ADC),
    // modified in place.
    void analog(double t_s, double ts_s, int n, double* i_A);
    // The converted samples at t (a frozen sample, a NaN), in place.
    void digital(double t_s, double ts_s, int n, double* i_meas_A);
    // The supply clamp at t, from the nominal one.
    double v_max_V(double t_s, double nominal_V) const;
    // The backend flags an overrun at t.
    bool overrun(double t_s, double ts_s) const;
    // The plant's faults at t: rotor held, the open winding (-1: none).
    bool rotor_locked(double t_s, double ts_s) const;
    int open_phase(double t_s, double ts_s) const;

private:
    FaultInjection f_;
    std::mt19937_64 rng_;
    bool stuck_held_ = false;
    double stuck_value_A_ = 0.0;
};

}  // namespace mcsim

#endif  // MCSIM_MODEL_FAULT_INJECTION_H
