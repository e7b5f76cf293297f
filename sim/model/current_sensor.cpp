#include "model/current_sensor.h"

#include <cmath>

namespace mcsim {

CurrentSensor::CurrentSensor(const SensorParams& p, std::uint64_t seed) : p_(p), rng_(seed)
{
    if (p_.adc_bits > 0) {
        const double codes = std::ldexp(1.0, p_.adc_bits);
        lsb_A_ = 2.0 * p_.adc_full_scale_A / codes;
        code_min_ = -codes / 2.0;
        code_max_ = codes / 2.0 - 1.0;
    }
}

double CurrentSensor::quantize(double i_A) const
{
    if (p_.adc_bits <= 0) {
        return i_A;
    }
    double code = std::floor(i_A / lsb_A_ + 0.5);
    code = (code < code_min_) ? code_min_ : ((code > code_max_) ? code_max_ : code);
    return code * lsb_A_;
}

void CurrentSensor::measure(double i_a_A, double i_b_A, double* i_a_meas_A, double* i_b_meas_A)
{
    double n_a = 0.0;
    double n_b = 0.0;
    switch (p_.noise) {
    case NoiseKind::kNone: break;
    case NoiseKind::kUniform:
        n_a = p_.noise_A * (2.0 * uniform01(rng_) - 1.0);
        n_b = p_.noise_A * (2.0 * uniform01(rng_) - 1.0);
        break;
    case NoiseKind::kGaussian: {
        // Box-Muller: one pair of uniforms gives the two independent normals
        // of the two phases. 1 - u keeps the log argument in (0, 1].
        const double u1 = 1.0 - uniform01(rng_);
        const double u2 = uniform01(rng_);
        const double r = p_.noise_A * std::sqrt(-2.0 * std::log(u1));
        const double phi = 6.283185307179586 * u2;
        n_a = r * std::cos(phi);
        n_b = r * std::sin(phi);
        break;
    }
    }
    *i_a_meas_A = quantize(i_a_A + n_a);
    *i_b_meas_A = quantize(i_b_A + n_b);
}

void CurrentSensor::measure_phases(int n, const double* i_A, double* i_meas_A)
{
    measure(i_A[0], i_A[1], &i_meas_A[0], &i_meas_A[1]);
    if (n == 3) {
        double unused = 0.0;
        measure(i_A[2], 0.0, &i_meas_A[2], &unused);
    }
}

}  // namespace mcsim
