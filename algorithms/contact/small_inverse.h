// The inverse of the 6×6 Cholesky factor the frictionless QP computes on
// every solve whose metric changed (the god-object's stiffness turned with
// the proxy, constrained dynamics' effective mass), written out at fixed
// size: Eigen's triangular solve with a matrix right-hand side takes its
// general blocked path at this size, about twice the instructions.
#pragma once

#include "hapticbench/pose.h"

namespace hb {

/// L⁻¹ of a lower-triangular L with a non-zero diagonal (itself lower
/// triangular), by forward substitution, column by column. The strict upper
/// part of `lower` is not read.
Mat6 lower_triangular_inverse(const Mat6& lower);

}  // namespace hb
