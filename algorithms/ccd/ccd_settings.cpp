#include "algorithms/ccd/ccd_settings.h"

#include <sstream>

#include "hapticbench/input_error.h"

namespace hb {

namespace {
std::string number_text(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}
}  // namespace

void validate_ccd_settings(const CcdSettings& settings, const std::string& field_prefix) {
  if (!(settings.time_tolerance >= 1e-12 && settings.time_tolerance <= 1))
    throw InputError("", field_prefix + ".time_tolerance",
                     "expected a fraction of the step in [1e-12, 1], got " +
                         number_text(settings.time_tolerance));
  if (settings.max_evaluations < 1)
    throw InputError("", field_prefix + ".max_evaluations",
                     "expected at least 1 sub-interval evaluation, got " +
                         std::to_string(settings.max_evaluations));
  if (!(settings.time_limit >= 0 && settings.time_limit <= 1))
    throw InputError(
        "", field_prefix + ".time_limit",
        "expected a fraction of the step in [0, 1], got " + number_text(settings.time_limit));
}

}  // namespace hb
