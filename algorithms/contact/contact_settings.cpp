#include "algorithms/contact/contact_settings.h"

#include <string>

#include "hapticbench/input_error.h"

namespace hb {

namespace {

// A distance (m) that must exceed the standoff (the proxy keeps that much).
double beyond_standoff(const ParamSet& params, const ContactSettings& settings, const char* key,
                       double fallback, double low, double high) {
  const double value = params.number(key, fallback, low, high);
  if (!(value > settings.standoff_m))
    throw InputError(
        "", params.field(key),
        "expected a distance larger than standoff (" + std::to_string(settings.standoff_m) + " m)");
  return value;
}

}  // namespace

void read_contact_distances(const ParamSet& params, ContactSettings& settings) {
  settings.standoff_m = params.number("standoff", settings.standoff_m, 1e-9, 1e-2);
  settings.contact_distance_m =
      beyond_standoff(params, settings, "contact_distance", settings.contact_distance_m, 1e-9, 1.0);
}

void read_contact_discovery(const ParamSet& params, ContactSettings& settings) {
  settings.ccd.primitive.time_tolerance =
      params.number("ccd_time_tolerance", settings.ccd.primitive.time_tolerance, 1e-12, 0.1);
  settings.ccd.primitive.max_evaluations = static_cast<int>(
      params.integer("ccd_max_evaluations", settings.ccd.primitive.max_evaluations, 1, 1000000));
  settings.ccd.contact_window =
      params.number("contact_window", settings.ccd.contact_window, 0.0, 1.0);
  settings.haptic_band_m =
      beyond_standoff(params, settings, "haptic_band", settings.haptic_band_m, 1e-6, 1.0);
  settings.haptic_band_min_m =
      beyond_standoff(params, settings, "haptic_band_min", settings.haptic_band_min_m, 1e-6,
                      settings.haptic_band_m);
  settings.haptic_max_pairs =
      static_cast<int>(params.integer("haptic_max_pairs", settings.haptic_max_pairs, 1, 100000));
}

ContactSettings read_contact_settings(const ParamSet& params, bool point_tool,
                                      const ContactSettings& defaults) {
  ContactSettings settings = defaults;
  settings.point_tool = point_tool;
  read_contact_distances(params, settings);
  read_contact_discovery(params, settings);
  return settings;
}

}  // namespace hb
