// Per-tick step times of a run, from its ticks CSV: the full distribution,
// where the summary holds only percentiles and an evenly spaced sample.
#pragma once

#include <filesystem>
#include <optional>
#include <vector>

namespace hb {

/// The step_ns column (ns of Renderer::step per tick, in tick order) of a
/// ticks_<label>.csv. Empty optional when the file does not exist. Throws
/// InputError(file, "line N", ...) when the file has no step_ns column or a
/// row's value is not a whole, non-negative number.
std::optional<std::vector<double>> read_ticks_step_ns(const std::filesystem::path& ticks_csv);

}  // namespace hb
