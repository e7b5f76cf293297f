// spectrum.h - how much of a sampled signal lies above a frequency: the
// chattering measure of paper 002's study (motorsim/ekf_speed_recorder.h).
// Eigen's FFT (unsupported/Eigen/FFT, kissfft inside) does the transform.
#ifndef MCSIM_MODEL_SPECTRUM_H
#define MCSIM_MODEL_SPECTRUM_H

#include <vector>

namespace mcsim {

// The RMS of x's content above f_cut_Hz, x sampled every ts_s: the mean
// removed, a Hann window, the bins above f_cut summed (both halves of the
// spectrum) and scaled by Parseval with the window's power, so a sine of
// amplitude A above f_cut reads A/sqrt(2) and one well below reads ~0.
// Fewer than 8 samples: 0.
double hf_rms(const std::vector<double>& x, double ts_s, double f_cut_Hz);

}  // namespace mcsim

#endif  // MCSIM_MODEL_SPECTRUM_H
