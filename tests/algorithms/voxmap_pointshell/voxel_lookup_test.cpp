// The voxmap's lookup arrays (algorithms/voxmap_pointshell/voxel_lookup.cpp)
// on a grid filled by hand: dense and uniform blocks side by side, so that
// the interpolation's eight corners fall in one block, in several, in
// uniform ones and beyond the arrays. Units m.
#include "algorithms/voxmap_pointshell/voxel_lookup.h"

#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <random>

namespace hb {
namespace {

constexpr double kVoxel = 0.001;  // m
constexpr float kOutside = 0.004f;

// 3 × 3 × 2 blocks from block (−1, −1, −1): dense blocks in a checkerboard
// (distinct distances per voxel), uniform ones between them with their own
// distance and state.
VoxelLookup checkerboard() {
  const Eigen::Vector3i block_min(-1, -1, -1);
  const Eigen::Vector3i block_count(3, 3, 2);
  VoxelLookup lookup(kVoxel, block_min, block_count, true, kOutside);
  std::mt19937 random(7);
  std::uniform_real_distribution<float> distance(-0.003f, 0.003f);
  for (int x = 0; x < block_count.x(); ++x) {
    for (int y = 0; y < block_count.y(); ++y) {
      for (int z = 0; z < block_count.z(); ++z) {
        const Eigen::Vector3i b(x, y, z);
        if ((x + y + z) % 2 == 0) {
          std::array<uint8_t, VoxelLookup::kBlockVoxels> states{};
          std::array<float, VoxelLookup::kBlockVoxels> distances{};
          for (int k = 0; k < VoxelLookup::kBlockVoxels; ++k) {
            distances[k] = distance(random);
            states[k] = static_cast<uint8_t>(distances[k] < 0       ? VoxelState::kInterior
                                             : distances[k] < 1e-3f ? VoxelState::kSurface
                                                                    : VoxelState::kProximity);
          }
          lookup.set_dense_block(b, states.data(), distances.data());
        } else {
          lookup.set_uniform_block(b, x == 1 ? VoxelState::kProximity : VoxelState::kFree,
                                   0.0005f * static_cast<float>(x + 2 * y + 3 * z));
        }
      }
    }
  }
  lookup.finish();
  return lookup;
}

// Trilinear interpolation of distance() at the eight corners, read one by one.
double reference_interpolation(const VoxelLookup& lookup, const Vec3& p, Vec3& gradient) {
  const Vec3 u = p / kVoxel;
  const Vec3 base = u.array().floor();
  const Vec3 f = u - base;
  const Eigen::Vector3i i0 = base.cast<int>();
  double c[2][2][2];
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b)
      for (int d = 0; d < 2; ++d) c[a][b][d] = lookup.distance(i0 + Eigen::Vector3i(a, b, d));
  double value = 0;
  gradient.setZero();
  for (int a = 0; a < 2; ++a) {
    for (int b = 0; b < 2; ++b) {
      for (int d = 0; d < 2; ++d) {
        const double wx = a ? f.x() : 1 - f.x(), wy = b ? f.y() : 1 - f.y(),
                     wz = d ? f.z() : 1 - f.z();
        const double sx = a ? 1 : -1, sy = b ? 1 : -1, sz = d ? 1 : -1;
        value += wx * wy * wz * c[a][b][d];
        gradient += Vec3(sx * wy * wz, wx * sy * wz, wx * wy * sz) * c[a][b][d] / kVoxel;
      }
    }
  }
  return value;
}

TEST_CASE("φ interpolates the stored distances wherever its corners lie", "[voxmap_pointshell]") {
  const VoxelLookup lookup = checkerboard();
  // The arrays span voxels [−8, 16) × [−8, 16) × [−8, 8); points from
  // beyond them on every side, so corners fall in one dense block, across
  // dense and uniform blocks, and outside.
  std::mt19937 random(11);
  std::uniform_real_distribution<double> xy(-0.0105, 0.0175), z(-0.0105, 0.0095);
  int across = 0, outside = 0, in_uniform = 0;
  for (int k = 0; k < 20000; ++k) {
    const Vec3 p(xy(random), xy(random), z(random));
    Vec3 gradient, expected_gradient;
    const double phi = lookup.interpolated_distance(p, gradient);
    const double expected = reference_interpolation(lookup, p, expected_gradient);
    INFO("point " << p.transpose());
    REQUIRE(phi == Approx(expected).margin(1e-12));
    REQUIRE((gradient - expected_gradient).norm() < 1e-9);
    // Voxel v of the arrays lies in block (v + 8) / 8 along each axis.
    const Eigen::Vector3i i0 = (p / kVoxel).array().floor().cast<int>();
    bool crosses = false, beyond = false;
    for (int axis = 0; axis < 3; ++axis) {
      const int end = axis < 2 ? 16 : 8;
      beyond = beyond || i0[axis] < -8 || i0[axis] + 1 >= end;
      crosses = crosses || (i0[axis] + 8) % 8 == 7;
    }
    outside += beyond;
    across += crosses && !beyond;
    // Eight corners in one uniform block (blocks with an odd sum of
    // coordinates): its own distance and no gradient, exactly.
    const Eigen::Vector3i block = (i0.array() + 8) / 8;
    if (!crosses && !beyond && block.sum() % 2 == 1) {
      ++in_uniform;
      REQUIRE(phi == static_cast<double>(lookup.distance(i0)));
      REQUIRE(gradient == Vec3::Zero());
    }
  }
  CHECK(across > 1000);
  CHECK(outside > 1000);
  CHECK(in_uniform > 1000);
}

TEST_CASE("a cell reads the same state and clearance as the world point it locates",
          "[voxmap_pointshell]") {
  const VoxelLookup lookup = checkerboard();
  std::mt19937 random(13);
  std::uniform_real_distribution<double> coordinate(-0.02, 0.03);
  for (int k = 0; k < 5000; ++k) {
    const Vec3 p(coordinate(random), coordinate(random), coordinate(random));
    const VoxelLookup::Cell cell = lookup.cell_at(p);
    const Eigen::Vector3i voxel = lookup.voxel_of(p);
    INFO("point " << p.transpose());
    REQUIRE(lookup.state(cell) == lookup.state(voxel));
    if (cell.inside) REQUIRE(lookup.voxel_of(cell) == voxel);
    REQUIRE(lookup.clearance(cell, p) == lookup.clearance(p));
  }
  // Not a number and far points are outside: free, with their clearance.
  const Vec3 nan = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  CHECK_FALSE(lookup.cell_at(nan).inside);
  CHECK(lookup.state(lookup.cell_at(nan)) == VoxelState::kFree);
  const Vec3 far(1e30, 0, 0);
  CHECK_FALSE(lookup.cell_at(far).inside);
  CHECK(lookup.clearance(lookup.cell_at(far), far) > 1e29);
}

}  // namespace
}  // namespace hb
