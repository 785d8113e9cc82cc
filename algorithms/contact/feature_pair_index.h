// Finding a feature pair in another certificate's list by value: an open
// addressing table over the list, kept between uses, so that matching two
// lists of n pairs is O(n) and does not allocate once the table has grown
// (a linear search per pair was O(n²): 256 pairs on a tiled floor).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "algorithms/ccd/mesh_ccd.h"

namespace hb {

class FeaturePairIndex {
 public:
  /// Indexes `pairs`, which must outlive the lookups (until the next build).
  void build(std::span<const ContactFeatures> pairs);
  /// The index in the list built of the first pair equal to `features`, or
  /// −1 when it lists none.
  int find(const ContactFeatures& features) const;

 private:
  std::size_t first_slot(const ContactFeatures& features) const;

  std::span<const ContactFeatures> pairs_;
  std::vector<int32_t> slots_;  ///< index into pairs_, −1 for an empty slot
  std::size_t mask_ = 0;        ///< slots_.size() − 1 (a power of two)
};

}  // namespace hb
