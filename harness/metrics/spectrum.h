// Spectral share of a sampled signal, for force jitter.
#pragma once

#include <vector>

namespace hb {

/// Fraction of the signal's energy (mean removed) at frequencies above
/// cutoff_hz, from its discrete Fourier transform (zero-padded to a power of
/// two). 0 for a constant or empty signal.
double energy_fraction_above(const std::vector<double>& signal, double sample_rate_hz,
                             double cutoff_hz);

}  // namespace hb
