#include "model/load_profile.h"

#include <cmath>

namespace mcsim {

LoadProfile::LoadProfile(const std::vector<LoadStep>& steps)
{
    double level = 0.0;
    for (const LoadStep& s : steps) {
        if (!knot_t_.empty()) {
            seg_cos_.push_back(false);  // the hold since the last step
        }
        knot_t_.push_back(s.t_s);
        knot_v_.push_back(level);
        seg_cos_.push_back(s.raised_cosine);  // the ramp
        knot_t_.push_back(s.t_s + s.ramp_s);
        knot_v_.push_back(s.torque_Nm);
        level = s.torque_Nm;
    }
}

double LoadProfile::torque_Nm(double t_s) const
{
    const std::size_t n = knot_t_.size();
    if (n == 0 || t_s < knot_t_[0]) {
        return 0.0;
    }
    // A handful of knots at most: a linear scan beats a binary search here,
    // from the last lookup's knot when t_s has not gone back before it
    // (knots are sorted: the scan ends on the last knot at or before t_s).
    std::size_t k = (hint_ < n && knot_t_[hint_] <= t_s) ? hint_ : 0;
    while (k + 1 < n && knot_t_[k + 1] <= t_s) {
        ++k;
    }
    hint_ = k;
    if (k + 1 == n) {
        return knot_v_[k];
    }
    const double dt = knot_t_[k + 1] - knot_t_[k];
    if (dt <= 0.0) {
        return knot_v_[k + 1];
    }
    double w = (t_s - knot_t_[k]) / dt;
    if (seg_cos_[k]) {
        w = 0.5 * (1.0 - std::cos(3.14159265358979323846 * w));
    }
    return knot_v_[k] + w * (knot_v_[k + 1] - knot_v_[k]);
}

}  // namespace mcsim
