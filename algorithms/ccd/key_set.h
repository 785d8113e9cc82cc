// A set of 64-bit keys in one flat table (open addressing, linear probing,
// a power-of-two number of slots kept at most half full): the proximity
// search inserts a key for every feature pair it finds within its
// threshold, most of them found again through a neighbouring leaf, and a
// node-based set (std::unordered_set) spent more on allocating and freeing
// its nodes than on the search's geometry.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace hb::ccd_detail {

class KeySet {
 public:
  /// Room for `expected` keys before the table grows.
  explicit KeySet(std::size_t expected = 128) {
    std::size_t slots = 16;
    shift_ = 64 - 4;
    while (slots < 2 * expected) {
      slots *= 2;
      --shift_;
    }
    slots_.assign(slots, kEmpty);
  }

  /// Adds the key; true when it was not there yet.
  bool insert(uint64_t key) {
    if (key == kEmpty) {  // the empty slot's marker, kept apart
      const bool added = !holds_empty_key_;
      holds_empty_key_ = true;
      return added;
    }
    if (2 * (stored_ + 1) > slots_.size()) grow();
    if (!place(key)) return false;
    ++stored_;
    return true;
  }

  /// Keys held.
  std::size_t size() const { return stored_ + (holds_empty_key_ ? 1 : 0); }

 private:
  static constexpr uint64_t kEmpty = ~uint64_t{0};

  // Fibonacci hashing: the keys' structured bits spread over the table.
  std::size_t slot_of(uint64_t key) const {
    return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> shift_);
  }

  // Puts the key in its slot or the first empty one after it; false when
  // it is already there.
  bool place(uint64_t key) {
    const std::size_t mask = slots_.size() - 1;
    for (std::size_t i = slot_of(key);; i = (i + 1) & mask) {
      if (slots_[i] == key) return false;
      if (slots_[i] == kEmpty) {
        slots_[i] = key;
        return true;
      }
    }
  }

  void grow() {
    std::vector<uint64_t> old(2 * slots_.size(), kEmpty);
    old.swap(slots_);
    --shift_;
    for (const uint64_t key : old)
      if (key != kEmpty) place(key);
  }

  std::vector<uint64_t> slots_;
  int shift_ = 0;           ///< 64 − log2(slots): the hash's top bits index the table
  std::size_t stored_ = 0;  ///< keys in the table (the empty marker aside)
  bool holds_empty_key_ = false;
};

}  // namespace hb::ccd_detail
