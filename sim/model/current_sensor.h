// current_sensor.h - the phase current measurement: additive noise (the
// hall-effect sensors of section 5.3, "precision of 1% of 3 A") followed by
// ADC quantization. Noise is drawn from std::mt19937_64, whose output the
// C++ standard fixes bit for bit, through this file's own uniform and
// Box-Muller transforms (std::uniform_real_distribution and
// std::normal_distribution are implementation-defined), so a seed gives the
// same run on every platform.
#ifndef MCSIM_MODEL_CURRENT_SENSOR_H
#define MCSIM_MODEL_CURRENT_SENSOR_H

#include <cstdint>
#include <random>

namespace mcsim {

enum class NoiseKind { kNone, kUniform, kGaussian };

struct SensorParams {
    NoiseKind noise = NoiseKind::kNone;
    // uniform: half-width (noise in [-noise_A, +noise_A]); gaussian: sigma.
    double noise_A = 0.0;
    int adc_bits = 0;               // 0 = no quantization
    double adc_full_scale_A = 0.0;  // input range [-fs, +fs)
};

// Uniform double in [0, 1) from the top 53 bits of one engine draw.
inline double uniform01(std::mt19937_64& rng)
{
    return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

class CurrentSensor {
public:
    CurrentSensor(const SensorParams& p, std::uint64_t seed);

    // One sample of both phases; noise is independent per phase and sample.
    void measure(double i_a_A, double i_b_A, double* i_a_meas_A, double* i_b_meas_A);

    // One sample of n (2 or 3) phases: the first two as measure(), the third
    // with a draw of its own after them (so 2-phase runs keep their noise).
    void measure_phases(int n, const double* i_A, double* i_meas_A);

    // Mid-tread quantizer with saturation at the ADC range; identity when
    // adc_bits == 0.
    double quantize(double i_A) const;

    const SensorParams& params() const { return p_; }

private:
    SensorParams p_;
    std::mt19937_64 rng_;
    double lsb_A_ = 0.0;
    double code_min_ = 0.0, code_max_ = 0.0;
};

}  // namespace mcsim

#endif  // MCSIM_MODEL_CURRENT_SENSOR_H
