#include "model/spectrum.h"

#include <cmath>
#include <complex>

#include <unsupported/Eigen/FFT>

namespace mcsim {

double hf_rms(const std::vector<double>& x, double ts_s, double f_cut_Hz)
{
    const std::size_t n = x.size();
    if (n < 8) {
        return 0.0;
    }
    double mean = 0.0;
    for (double v : x) {
        mean += v;
    }
    mean /= static_cast<double>(n);
    constexpr double kPi = 3.14159265358979323846;
    std::vector<double> y(n);
    double w2 = 0.0;
    for (std::size_t k = 0; k < n; ++k) {
        const double w = 0.5 * (1.0 - std::cos(2.0 * kPi * static_cast<double>(k) / static_cast<double>(n)));
        y[k] = w * (x[k] - mean);
        w2 += w * w;
    }
    Eigen::FFT<double> fft;
    std::vector<std::complex<double>> Y;
    fft.fwd(Y, y);  // the full spectrum (Eigen's FFT returns both halves for real input by default)
    const double df = 1.0 / (static_cast<double>(n) * ts_s);
    double p = 0.0;
    for (std::size_t k = 1; k < Y.size(); ++k) {
        const std::size_t kk = (k <= n / 2) ? k : n - k;
        if (static_cast<double>(kk) * df > f_cut_Hz) {
            p += std::norm(Y[k]);
        }
    }
    // Parseval: sum |Y_k|^2 = n sum y_k^2, and sum y_k^2 ~ (sum w_k^2) x_rms^2
    return std::sqrt(p / (static_cast<double>(n) * w2));
}

}  // namespace mcsim
