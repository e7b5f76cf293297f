#include "model/encoder.h"

#include <cmath>

namespace mcsim {

namespace {
constexpr double kTwoPi = 6.283185307179586476925286766559;
}

Encoder::Encoder(const EncoderParams& p, std::uint64_t seed) : p_(p), rng_(seed ^ 0xE4C0DEu) {}

double Encoder::measure(double theta_rad)
{
    const double step = kTwoPi / static_cast<double>(p_.counts_per_turn);
    double th = std::floor(theta_rad / step) * step;
    if (p_.noise_rad > 0.0) {
        th += p_.noise_rad * n01_(rng_);
    }
    return th - kTwoPi * std::floor((th + 0.5 * kTwoPi) / kTwoPi);  // [-pi, pi)
}

}  // namespace mcsim
