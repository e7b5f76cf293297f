// run_watch.h - what went wrong in a run, and when: the drive's first fault
// (code, time, the measured current at that sample) and the first sample
// where the plant left what physics allows (a non-finite state, a current
// beyond the supply's reach, a speed beyond the no-load speed). Fed once per
// period by the recorders; motorsim turns it into the exit status and the
// message on stderr (motorsim --help lists both).
#ifndef MCSIM_MOTORSIM_RUN_WATCH_H
#define MCSIM_MOTORSIM_RUN_WATCH_H

#include <cstdint>
#include <string>

#include "hal_sw_plant.h"
#include "model/pm_plant.h"
#include "scenario/scenario.h"

namespace mcsim {

class RunWatch {
public:
    // The physical envelope of sc's motor and supply (see run_watch.cpp).
    explicit RunWatch(const Scenario& sc);

    // One period: the sensor output and the drive's fault code after its
    // step, the plant at the sampling instant.
    void on_period(const hal_sw_plant_period_t& p, std::int64_t fault, const PmPlant& plant);

    bool faulted() const { return fault_ != 0; }
    std::int64_t fault() const { return fault_; }
    double fault_t_s() const { return fault_t_; }
    double fault_i_meas_A() const { return fault_i_; }  // largest |measured phase current| at the fault
    bool diverged() const { return !diverged_what_.empty(); }
    double diverged_t_s() const { return diverged_t_; }
    const std::string& diverged_what() const { return diverged_what_; }  // "i_a_A = 1e300 A beyond 2000 A"

    double i_envelope_A() const { return i_env_; }
    double omega_envelope_rad_s() const { return w_env_; }

private:
    double i_env_, w_env_;
    std::int64_t fault_ = 0;
    double fault_t_ = -1.0, fault_i_ = 0.0;
    double diverged_t_ = -1.0;
    std::string diverged_what_;
};

}  // namespace mcsim

#endif  // MCSIM_MOTORSIM_RUN_WATCH_H
