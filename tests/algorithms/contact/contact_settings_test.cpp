// The contact keys shared by the god-object and constrained dynamics: read
// with their field names, defaults for absent keys, checked in their
// documented order.
#include "algorithms/contact/contact_settings.h"

#include <catch2/catch.hpp>

#include "hapticbench/input_error.h"

namespace hb {
namespace {

TEST_CASE("contact settings are read with their field names") {
  ParamSet params("/algorithms/0/params");
  params.set("standoff", 2e-5);
  params.set("contact_distance", 3e-4);
  params.set("ccd_time_tolerance", 1e-7);
  params.set("ccd_max_evaluations", 128.0);
  params.set("contact_window", 2e-3);
  params.set("haptic_band", 4e-3);
  params.set("haptic_band_min", 1e-3);
  params.set("haptic_max_pairs", 32.0);
  const ContactSettings read = read_contact_settings(params, true);
  CHECK(read.point_tool);
  CHECK(read.standoff_m == 2e-5);
  CHECK(read.contact_distance_m == 3e-4);
  CHECK(read.ccd.primitive.time_tolerance == 1e-7);
  CHECK(read.ccd.primitive.max_evaluations == 128);
  CHECK(read.ccd.contact_window == 2e-3);
  CHECK(read.haptic_band_m == 4e-3);
  CHECK(read.haptic_band_min_m == 1e-3);
  CHECK(read.haptic_max_pairs == 32);
  CHECK_NOTHROW(params.reject_unknown());
}

TEST_CASE("absent contact keys take the given defaults") {
  ContactSettings defaults;
  defaults.haptic_max_pairs = 256;
  const ContactSettings read = read_contact_settings(ParamSet("/p"), false, defaults);
  CHECK_FALSE(read.point_tool);
  CHECK(read.haptic_max_pairs == 256);
  CHECK(read.standoff_m == ContactSettings{}.standoff_m);
  CHECK(read.haptic_band_m == ContactSettings{}.haptic_band_m);
}

TEST_CASE("bad contact keys are named, the first in reading order") {
  ParamSet params("/algorithms/0/params");
  params.set("haptic_band", 1e-6);  // not beyond the standoff
  params.set("contact_window", 2.0);
  CHECK_THROWS_WITH(read_contact_settings(params, false),
                    Catch::Contains("/algorithms/0/params/contact_window"));
  params.set("contact_window", 1e-3);
  CHECK_THROWS_WITH(read_contact_settings(params, false),
                    Catch::Contains("/algorithms/0/params/haptic_band") &&
                        Catch::Contains("larger than standoff"));
  ParamSet close("/algorithms/0/params");
  close.set("standoff", 1e-3);
  close.set("contact_distance", 1e-4);
  CHECK_THROWS_WITH(read_contact_settings(close, false),
                    Catch::Contains("/algorithms/0/params/contact_distance"));
}

}  // namespace
}  // namespace hb
