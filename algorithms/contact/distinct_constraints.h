// Constraints that repeat exactly: every number of one equal, bit for bit,
// to another's, and the same μ. Crowded contact makes them — the corner
// four tiles share is a scene vertex of each tile, and each makes the same
// constraint on the tool face above it — and the constrained step treats
// them as one: the frictionless QP never takes more than one of equal rows
// into its active set (the others depend on it), and the frictional solve
// merges contacts at one point with one normal. Solving the distinct ones
// only gives the same step, and the same impulses (the first of equal
// constraints carries them, the others nothing), at the cost of the
// distinct rows instead of all.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "algorithms/contact/gauss_least_constraint.h"
#include "hapticbench/pose.h"

namespace hb {

class DistinctConstraints {
 public:
  /// Up to this many constraints the repeats are not looked for: the
  /// search would cost about what they do in the solve.
  static constexpr std::size_t kFewConstraints = 32;

  /// Finds the repeats among `constraints` (friction: one μ per constraint,
  /// or empty); returns whether there are any (false for kFewConstraints or
  /// fewer). Reusable buffers: no allocation once they have grown.
  bool reduce(std::span<const GaussConstraint> constraints, std::span<const double> friction);

  /// After reduce returned true: the distinct constraints in the order of
  /// their first occurrence, and their μ (empty when none was given).
  std::span<const GaussConstraint> constraints() const { return distinct_; }
  std::span<const double> friction() const { return distinct_friction_; }
  /// The distinct constraint that constraint k of the last reduce repeats (or is).
  int distinct_of(int k) const { return distinct_of_[static_cast<std::size_t>(k)]; }
  /// The first occurrence of distinct constraint d in the last reduce's constraints.
  int first_of(int d) const { return first_of_[static_cast<std::size_t>(d)]; }

 private:
  std::vector<GaussConstraint> distinct_;
  std::vector<double> distinct_friction_;
  std::vector<int> distinct_of_;
  std::vector<int> first_of_;
  struct Slot {
    uint32_t stamp = 0;  ///< the call that filled it
    int32_t distinct = -1;
  };
  std::vector<Slot> slots_;  ///< open addressing by lever, linear probing
  uint32_t stamp_ = 0;       ///< this call's
};

}  // namespace hb
