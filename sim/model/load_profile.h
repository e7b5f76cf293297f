// load_profile.h - external load torque T_load(t) of the plant: piecewise
// constant steps, each optionally reached by a ramp, linear or a raised
// cosine (paper 002's pulses: 0.5 (1 - cos(pi x)) of the change at x in
// [0, 1] of the edge, smooth in the torque's derivative).
#ifndef MCSIM_MODEL_LOAD_PROFILE_H
#define MCSIM_MODEL_LOAD_PROFILE_H

#include <cstddef>
#include <vector>

namespace mcsim {

struct LoadStep {
    double t_s = 0.0;        // when the change starts
    double torque_Nm = 0.0;  // level reached (positive opposes positive speed)
    double ramp_s = 0.0;     // 0 = a step; > 0 = a ramp from the previous level
    bool raised_cosine = false;  // the ramp's shape: linear, or a raised cosine
};

class LoadProfile {
public:
    LoadProfile() = default;
    // Steps must be sorted with t_s[i+1] >= t_s[i] + ramp_s[i] (the scenario
    // parser checks this); the level is 0 before the first step.
    explicit LoadProfile(const std::vector<LoadStep>& steps);

    double torque_Nm(double t_s) const;
    bool empty() const { return knot_t_.empty(); }

private:
    // Knots of the piecewise-linear profile; two knots at the same time make a step.
    std::vector<double> knot_t_, knot_v_;
    std::vector<bool> seg_cos_;  // segment k (knot k to k+1) is a raised cosine
    // Where the last lookup ended: the plant asks at t, t + Ts/2, t + Ts
    // and the recorder at t again, so the next lookup starts here rather
    // than at the first knot (the same knot is found either way).
    mutable std::size_t hint_ = 0;
};

}  // namespace mcsim

#endif  // MCSIM_MODEL_LOAD_PROFILE_H
