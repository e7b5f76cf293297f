#include "model/board_emulation.h"

#include <algorithm>
#include <cmath>

namespace mcsim {

BoardEmulation::BoardEmulation(const BoardParams& p, std::uint64_t seed) : p_(p), rng_(seed ^ 0xB0A2Du)
{
    board_chain_init(&chain_, &p.chain);
}

uint32_t BoardEmulation::adc(double v)
{
    if (p_.noise_V > 0.0) {
        v += p_.noise_V * noise_(rng_);
    }
    return board_volts_to_code(v, p_.chain.adc_bits, p_.chain.adc_range_V);
}

bool BoardEmulation::calibrate(std::string* why)
{
    const int n_ph = std::min(p_.chain.n_phases, BOARD_MAX_PHASES);
    double sum[BOARD_MAX_PHASES] = {};
    for (int s = 0; s < p_.calibration_samples; ++s) {
        for (int k = 0; k < n_ph; ++k) {
            // no current: the sensor's offset, the noise, the converter
            sum[k] += board_code_to_volts(adc(p_.sensor_offset_V[k]), p_.chain.adc_bits, p_.chain.adc_range_V);
        }
    }
    char err[240];
    if (!board_chain_calibrate(&chain_, sum, p_.calibration_samples, err, sizeof err)) {
        if (why != nullptr) *why = err;
        return false;
    }
    return true;
}

void BoardEmulation::measure(int n, const double* i_true_A, double v_bus_true_V, double* i_meas_A,
                             double* v_bus_meas_V)
{
    for (int k = 0; k < n; ++k) {
        const double g = p_.chain.sensor_V_per_A * (1.0 + p_.sensor_gain_error[k]);
        const double v = std::isfinite(i_true_A[k]) ? i_true_A[k] * g + p_.sensor_offset_V[k] : i_true_A[k];
        i_meas_A[k] = std::isfinite(v) ? board_current_A(&chain_, k, adc(v)) : v;
    }
    if (p_.chain.vbus_ai >= 0) {
        *v_bus_meas_V = board_vbus_V(&chain_, adc(v_bus_true_V / p_.chain.vbus_V_per_V));
    } else {
        *v_bus_meas_V = board_vbus_V(&chain_, 0u);
    }
}

void BoardEmulation::apply(int n, const double* v_cmd_V, double v_supply_V, double* v_out_V)
{
    for (int k = 0; k < n; ++k) {
        const uint32_t code = board_voltage_code(&chain_, v_cmd_V[k], nullptr);
        const double u = board_code_to_volts(code, p_.chain.dac_bits, p_.chain.dac_range_V);
        v_out_V[k] = std::clamp(u * p_.chain.amplifier_V_per_V, -v_supply_V, v_supply_V);
    }
}

}  // namespace mcsim
