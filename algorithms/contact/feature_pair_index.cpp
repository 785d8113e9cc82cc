#include "algorithms/contact/feature_pair_index.h"

#include <algorithm>
#include <bit>

namespace hb {

std::size_t FeaturePairIndex::first_slot(const ContactFeatures& f) const {
  // The four fields mixed into 64 bits (splitmix64's finaliser).
  uint64_t h = (static_cast<uint64_t>(f.kind) << 60) ^
               (static_cast<uint64_t>(static_cast<uint32_t>(f.scene_object)) << 42) ^
               (static_cast<uint64_t>(static_cast<uint32_t>(f.tool_feature)) << 21) ^
               static_cast<uint64_t>(static_cast<uint32_t>(f.scene_feature));
  h ^= h >> 30;
  h *= 0xbf58476d1ce4e5b9ULL;
  h ^= h >> 27;
  h *= 0x94d049bb133111ebULL;
  h ^= h >> 31;
  return static_cast<std::size_t>(h) & mask_;
}

void FeaturePairIndex::build(std::span<const ContactFeatures> pairs) {
  pairs_ = pairs;
  // At most half full, so that a probe ends soon at an empty slot.
  const std::size_t size = std::bit_ceil(std::max<std::size_t>(2 * pairs.size(), 4));
  slots_.assign(size, -1);
  mask_ = size - 1;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    std::size_t slot = first_slot(pairs[i]);
    while (slots_[slot] >= 0 && pairs_[static_cast<std::size_t>(slots_[slot])] != pairs[i])
      slot = (slot + 1) & mask_;
    if (slots_[slot] < 0) slots_[slot] = static_cast<int32_t>(i);  // a repeat keeps the first
  }
}

int FeaturePairIndex::find(const ContactFeatures& features) const {
  if (slots_.empty()) return -1;
  for (std::size_t slot = first_slot(features);; slot = (slot + 1) & mask_) {
    const int32_t i = slots_[slot];
    if (i < 0) return -1;
    if (pairs_[static_cast<std::size_t>(i)] == features) return i;
  }
}

}  // namespace hb
