// Settings of the constrained-contact renderers' contact handling, shared by
// the god-object and constrained dynamics: the standoff the proxy keeps
// from the scene, when a feature pair counts as a contact, the mesh CCD's
// settings (the start escape, the god-object's moves), and the proximity
// certificates' bands and pair limit (proximity_certifier.h).
#pragma once

#include "algorithms/ccd/mesh_ccd.h"
#include "hapticbench/param_set.h"

namespace hb {

struct ContactSettings {
  MeshCcdSettings ccd;
  /// Separation (m) the proxy keeps from the surfaces it touches, > 0: the
  /// CCD's answer "no contact before t" holds for the path, so the proxy
  /// stops this far short of the touching point and later sliding motions
  /// start from a configuration the CCD can prove contact-free.
  double standoff_m = 1e-5;
  /// A pair whose features are farther apart than this (m) is no contact.
  double contact_distance_m = 1e-4;
  /// The tool is the point at its frame's origin (the 3-DOF god-object).
  bool point_tool = false;
  /// Contact discovery for the haptic-rate solve (proximity_certifier.h):
  /// feature pairs within the band (m) of the proxy are listed, and the
  /// proxy may move up to about this far between slow updates. The band is
  /// six times how far the device moved between the last two slow updates
  /// (the certificate must last until the next one is installed, up to two
  /// such intervals, with a margin of three), within [haptic_band_min_m,
  /// haptic_band_m].
  double haptic_band_m = 5e-3;
  double haptic_band_min_m = 5e-4;
  /// At most this many pairs are listed (the nearest); the band shrinks to
  /// the nearest pair left out. A query lists kFirstListedPairs first and
  /// this many only when those leave less reach than the band asks for
  /// (ProximityCertifier::certify; why both numbers: docs/performance.md,
  /// "How many pairs a certificate lists").
  int haptic_max_pairs = 2048;
};

/// Reads "standoff" (m, default 1e-5), "contact_distance" (m, > standoff,
/// default 1e-4), "ccd_time_tolerance" (default 1e-6),
/// "ccd_max_evaluations" (default 64), "contact_window" (default 1e-3),
/// "haptic_band" (m, > standoff, default 5e-3), "haptic_band_min" (m,
/// default 5e-4) and "haptic_max_pairs" (default 2048), in that order;
/// `defaults` gives the values of absent keys. Throws InputError naming the
/// field.
ContactSettings read_contact_settings(const ParamSet& params, bool point_tool,
                                      const ContactSettings& defaults = {});

/// The two halves of read_contact_settings, for a renderer that reads a key
/// of its own between them (the god-object's "max_iterations"), so that its
/// fields are checked, and a bad one named, in the order it documents:
/// "standoff" and "contact_distance" ...
void read_contact_distances(const ParamSet& params, ContactSettings& settings);
/// ... then the CCD's keys, the bands and the pair limit.
void read_contact_discovery(const ParamSet& params, ContactSettings& settings);

}  // namespace hb
