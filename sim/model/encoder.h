// encoder.h - a rotor position encoder for the HAL's optional position
// input (hal_sample_t.has_angle, angle_rad; paper 002 measures theta_r):
// the mechanical angle quantised to counts_per_turn (the count the
// encoder's edge has passed: floor), plus Gaussian angle noise of
// noise_rad, wrapped into [-pi, pi) as an absolute encoder reports it.
#ifndef MCSIM_MODEL_ENCODER_H
#define MCSIM_MODEL_ENCODER_H

#include <cstdint>
#include <random>

namespace mcsim {

struct EncoderParams {
    std::int64_t counts_per_turn = 0;  // 0: no encoder
    double noise_rad = 0.0;            // Gaussian sigma
    bool present() const { return counts_per_turn > 0; }
};

class Encoder {
public:
    Encoder(const EncoderParams& p, std::uint64_t seed);
    double measure(double theta_rad);

private:
    EncoderParams p_;
    std::mt19937_64 rng_;
    std::normal_distribution<double> n01_{0.0, 1.0};
};

}  // namespace mcsim

#endif  // MCSIM_MODEL_ENCODER_H
