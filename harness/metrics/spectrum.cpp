#include "harness/metrics/spectrum.h"

#include <cmath>
#include <complex>
#include <numbers>

namespace hb {

namespace {
// In-place iterative radix-2 FFT; data.size() is a power of two.
void fft(std::vector<std::complex<double>>& data) {
  const std::size_t n = data.size();
  for (std::size_t i = 1, j = 0; i < n; ++i) {
    std::size_t bit = n >> 1;
    for (; j & bit; bit >>= 1) j ^= bit;
    j ^= bit;
    if (i < j) std::swap(data[i], data[j]);
  }
  for (std::size_t len = 2; len <= n; len <<= 1) {
    const double angle = -2.0 * std::numbers::pi / static_cast<double>(len);
    const std::complex<double> step(std::cos(angle), std::sin(angle));
    for (std::size_t start = 0; start < n; start += len) {
      std::complex<double> w(1.0, 0.0);
      for (std::size_t k = 0; k < len / 2; ++k) {
        const std::complex<double> even = data[start + k];
        const std::complex<double> odd = data[start + k + len / 2] * w;
        data[start + k] = even + odd;
        data[start + k + len / 2] = even - odd;
        w *= step;
      }
    }
  }
}
}  // namespace

double energy_fraction_above(const std::vector<double>& signal, double sample_rate_hz,
                             double cutoff_hz) {
  if (signal.size() < 2) return 0.0;
  double mean = 0;
  for (double x : signal) mean += x;
  mean /= static_cast<double>(signal.size());
  std::size_t n = 1;
  while (n < signal.size()) n <<= 1;
  std::vector<std::complex<double>> data(n, 0.0);
  for (std::size_t i = 0; i < signal.size(); ++i) data[i] = signal[i] - mean;
  fft(data);
  double total = 0, above = 0;
  for (std::size_t k = 1; k <= n / 2; ++k) {
    const double frequency = sample_rate_hz * static_cast<double>(k) / static_cast<double>(n);
    const double power = std::norm(data[k]);
    total += power;
    if (frequency > cutoff_hz) above += power;
  }
  return total > 0 ? above / total : 0.0;
}

}  // namespace hb
