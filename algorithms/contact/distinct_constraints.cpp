#include "algorithms/contact/distinct_constraints.h"

#include <bit>
#include <cstring>

namespace hb {
namespace {

static_assert(sizeof(GaussConstraint) == 7 * sizeof(double),
              "a constraint's bytes are its seven numbers, no padding");

// Equal bit for bit (so −0 and +0 differ, and equal NaNs match: either way
// nothing is merged that the solve would treat differently).
bool same(const GaussConstraint& a, double mu_a, const GaussConstraint& b, double mu_b) {
  return std::memcmp(&a, &b, sizeof(GaussConstraint)) == 0 &&
         std::bit_cast<uint64_t>(mu_a) == std::bit_cast<uint64_t>(mu_b);
}

// The lever tells contacts apart; equal constraints share a slot.
uint64_t hash_of(const GaussConstraint& c) {
  constexpr uint64_t kOdd = 0x9E3779B97F4A7C15ULL;
  uint64_t h = std::bit_cast<uint64_t>(c.lever.x()) * kOdd;
  h = (h ^ std::bit_cast<uint64_t>(c.lever.y())) * kOdd;
  h = (h ^ std::bit_cast<uint64_t>(c.lever.z())) * kOdd;
  return h ^ (h >> 32);
}

}  // namespace

bool DistinctConstraints::reduce(std::span<const GaussConstraint> constraints,
                                 std::span<const double> friction) {
  const std::size_t count = constraints.size();
  if (count <= kFewConstraints) return false;
  const bool with_friction = !friction.empty();
  std::size_t table = 64;
  while (table < 2 * count) table *= 2;
  // A slot belongs to this call when its stamp is this call's: the table
  // is cleared only when the stamps wrap or it grows.
  if (slots_.size() != table || ++stamp_ == 0) {
    slots_.assign(table, Slot{});
    stamp_ = 1;
  }
  distinct_.clear();
  distinct_friction_.clear();
  distinct_of_.resize(count);
  first_of_.clear();
  for (std::size_t k = 0; k < count; ++k) {
    const GaussConstraint& c = constraints[k];
    const double mu = with_friction ? friction[k] : 0.0;
    std::size_t slot = hash_of(c) & (table - 1);
    int found = -1;
    for (; slots_[slot].stamp == stamp_; slot = (slot + 1) & (table - 1)) {
      const auto d = static_cast<std::size_t>(slots_[slot].distinct);
      if (same(distinct_[d], with_friction ? distinct_friction_[d] : 0.0, c, mu)) {
        found = slots_[slot].distinct;
        break;
      }
    }
    if (found < 0) {
      found = static_cast<int>(distinct_.size());
      slots_[slot] = Slot{stamp_, found};
      distinct_.push_back(c);
      if (with_friction) distinct_friction_.push_back(mu);
      first_of_.push_back(static_cast<int>(k));
    }
    distinct_of_[k] = found;
  }
  return distinct_.size() < count;
}

}  // namespace hb
