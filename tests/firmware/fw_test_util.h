// fw_test_util.h - small helpers shared by the firmware unit tests.
#ifndef TESTS_FIRMWARE_FW_TEST_UTIL_H
#define TESTS_FIRMWARE_FW_TEST_UTIL_H

extern "C" {
#include "estimators/emf_observer.h"
#include "math/mc_convert.h"
}

namespace fwtest {

constexpr double kPi = 3.14159265358979323846;
inline mc_t M(double x) { return mc_from_double(x); }
inline double D(mc_t x) { return mc_to_double(x); }

// Gains of the back-EMF observer (25) in the per-sample, voltage-scaled
// form emf_observer_config_t stores them.
inline emf_observer_config_t emf_config(double L, double Ts, double alpha, double lambda, double l, double lpf)
{
    emf_observer_config_t c{};
    c.lambda_A = M(lambda * Ts);
    c.l_ts = M(l * Ts);
    c.alpha_V = M(L * alpha * Ts);
    c.alpha_V_s = M(L * alpha);
    c.lpf_coeff = M(lpf);
    return c;
}

}  // namespace fwtest

#endif  // TESTS_FIRMWARE_FW_TEST_UTIL_H
