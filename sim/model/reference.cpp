#include "model/reference.h"

namespace mcsim {

Reference::Reference(const std::vector<Segment>& segs, double theta_start_rad)
    : segs_(segs), theta_start_rad_(theta_start_rad)
{
    double from = theta_start_rad;
    for (const Segment& s : segs_) {
        from_rad_.push_back(from);
        from = s.theta_to_rad;
    }
}

double Reference::final_theta_rad() const
{
    return segs_.empty() ? theta_start_rad_ : segs_.back().theta_to_rad;
}

RefPoint Reference::eval(double t_s) const
{
    RefPoint r;
    r.theta_rad = theta_start_rad_;
    for (std::size_t k = 0; k < segs_.size(); ++k) {
        const Segment& s = segs_[k];
        if (t_s < s.t_start_s) {
            break;  // holding before segment k
        }
        const double t_end = s.t_start_s + s.duration_s;
        if (t_s >= t_end) {
            r.theta_rad = s.theta_to_rad;
            continue;
        }
        const double T = s.duration_s;
        const double D = (t_s - s.t_start_s) / T;
        const double D2 = D * D;
        const double D3 = D2 * D;
        // p = 35D^4 - 84D^5 + 70D^6 - 20D^7 and its derivatives in D.
        const double p = D3 * D * (35.0 + D * (-84.0 + D * (70.0 - 20.0 * D)));
        const double dp = D3 * (140.0 + D * (-420.0 + D * (420.0 - 140.0 * D)));
        const double ddp = D2 * (420.0 + D * (-1680.0 + D * (2100.0 - 840.0 * D)));
        const double dtheta = s.theta_to_rad - from_rad_[k];
        r.theta_rad = from_rad_[k] + dtheta * p;
        r.omega_rad_s = dtheta * dp / T;
        r.accel_rad_s2 = dtheta * ddp / (T * T);
        break;
    }
    return r;
}

}  // namespace mcsim
