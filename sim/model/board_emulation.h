// board_emulation.h - a DAC/ADC board emulated around the plant
// (motorsim --backend board-emulated): Hall-effect current sensors with
// their true gains (the nominal one times 1 + a gain error) and offsets,
// Gaussian noise at the A/D input, the A/D and D/A converters (bits,
// +-range, clamping), the linear amplifiers clamped at the supply. The
// drive's side of the chain (codes to amperes with the calibrated
// offsets, volts to codes) is the same C as the real board's
// (hal/backends/board/board_chain.h). The start-up calibration measures
// the offsets with the outputs at zero before the drive starts.
#ifndef MCSIM_MODEL_BOARD_EMULATION_H
#define MCSIM_MODEL_BOARD_EMULATION_H

#include <cstdint>
#include <random>
#include <string>

#include "board_chain.h"

namespace mcsim {

// [board] of a scenario: the chain (channel map, converters, gains) and
// the emulated hardware's imperfections.
struct BoardParams {
    board_chain_config_t chain{};
    int calibration_samples = 1000;
    double sensor_offset_V[3] = {0.0, 0.0, 0.0};   // the sensors' true offsets
    double sensor_gain_error[3] = {0.0, 0.0, 0.0}; // true gain = nominal (1 + error)
    double noise_V = 0.0;                          // Gaussian sigma at the A/D input
};

class BoardEmulation {
public:
    BoardEmulation(const BoardParams& p, std::uint64_t seed);

    // The start-up calibration with the outputs at zero (no current):
    // false with the reason if an offset is out of range.
    bool calibrate(std::string* why);

    // Measured phase currents [A] from the true ones, through sensor, A/D
    // and the chain; the bus voltage through its channel (or nominal).
    void measure(int n, const double* i_true_A, double v_bus_true_V, double* i_meas_A, double* v_bus_meas_V);

    // The phase voltages the amplifiers put out for the drive's command
    // (chain, D/A, amplifier gain, clamp at v_supply).
    void apply(int n, const double* v_cmd_V, double v_supply_V, double* v_out_V);

    const board_chain_t& chain() const { return chain_; }

private:
    uint32_t adc(double v);
    BoardParams p_;
    board_chain_t chain_;
    std::mt19937_64 rng_;
    std::normal_distribution<double> noise_{0.0, 1.0};
};

}  // namespace mcsim

#endif  // MCSIM_MODEL_BOARD_EMULATION_H
