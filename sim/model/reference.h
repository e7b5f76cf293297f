// reference.h - the reference trajectory of paper 000 section 5.2 in double
// precision, independent of the firmware's: chained rest-to-rest moves of
// eq. (70) in the errata form
//   theta_r = theta_i + (theta_f - theta_i)(35D^4 - 84D^5 + 70D^6 - 20D^7),
//   D = (t - t_i)/(t_f - t_i).
// The simulator scores tracking against this one, so a trajectory bug in the
// firmware cannot hide in the metrics.
#ifndef MCSIM_MODEL_REFERENCE_H
#define MCSIM_MODEL_REFERENCE_H

#include <vector>

namespace mcsim {

struct Segment {
    double t_start_s = 0.0;
    double duration_s = 0.0;
    double theta_to_rad = 0.0;
};

struct RefPoint {
    double theta_rad = 0.0, omega_rad_s = 0.0, accel_rad_s2 = 0.0;
};

class Reference {
public:
    Reference() = default;
    // Segments sorted and non-overlapping; each starts where the previous ended.
    explicit Reference(const std::vector<Segment>& segs, double theta_start_rad = 0.0);

    RefPoint eval(double t_s) const;
    double final_theta_rad() const;

private:
    std::vector<Segment> segs_;
    std::vector<double> from_rad_;
    double theta_start_rad_ = 0.0;
};

}  // namespace mcsim

#endif  // MCSIM_MODEL_REFERENCE_H
