// The scene voxmap as the haptic loop reads it: plain arrays filled once
// from the OpenVDB grids (voxmap.cpp), so a lookup is two memory reads.
//
// Grid: voxel (i, j, k) is the cube of edge h centred on the world point
// h·(i, j, k) (OpenVDB's cell-centred index space with a linear transform of
// voxel size h). The arrays cover a box of whole blocks of 8³ voxels, the
// same blocks as OpenVDB's leaf nodes; everything outside the box is free.
// A block is either uniform (one state, no per-voxel storage) or dense (one
// state byte per voxel, and for the signed-distance variant one float).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "hapticbench/pose.h"

namespace hb {

/// McNeely et al.'s voxel states.
enum class VoxelState : uint8_t {
  kFree = 0,       ///< outside the scene, beyond the proximity layers
  kInterior = 1,   ///< inside the scene, more than half a voxel below its surface
  kSurface = 2,    ///< centre within half a voxel of the surface
  kProximity = 3,  ///< outside, centre within the proximity layers
};

class VoxelLookup {
 public:
  static constexpr int kBlockLog2 = 3;
  static constexpr int kBlockEdge = 1 << kBlockLog2;  ///< voxels per block edge
  static constexpr int kBlockVoxels = kBlockEdge * kBlockEdge * kBlockEdge;
  /// Blocks this close (Chebyshev, in blocks) to a non-free one keep a
  /// per-voxel clearance, exact up to kFineCap voxels.
  static constexpr int kFineBlocks = 1;
  static constexpr int kFineCap = kFineBlocks * kBlockEdge;

  /// An empty lookup: every point is free.
  VoxelLookup() = default;

  /// Sizes the arrays for blocks [block_min, block_min + block_count) of
  /// voxel size h (m); all uniform free until set. outside_distance_m: the
  /// signed distance read outside the arrays (the exterior band, m).
  VoxelLookup(double voxel_size_m, const Eigen::Vector3i& block_min,
              const Eigen::Vector3i& block_count, bool with_distances, float outside_distance_m);

  /// Makes block b (index relative to block_min) uniform; `distance` (m) is
  /// what the signed-distance variant reads anywhere in it.
  void set_uniform_block(const Eigen::Vector3i& b, VoxelState state, float distance);
  /// Makes block b dense with 512 states and (with distances) 512 signed
  /// distances at the voxel centres, both in OpenVDB's leaf order
  /// (x major: local index (x << 6) | (y << 3) | z).
  void set_dense_block(const Eigen::Vector3i& b, const uint8_t* states, const float* distances);
  /// Computes the clearance maps: per block, the Chebyshev distance in
  /// blocks to the nearest block holding a non-free voxel (saturated at
  /// 255), and per voxel of the blocks at most kFineBlocks from one, the
  /// Chebyshev distance in voxels to the nearest non-free voxel (exact up to
  /// kFineCap, kFineCap + 1 beyond). Call once after filling.
  void finish();

  double voxel_size() const { return h_; }
  bool has_distances() const { return with_distances_; }

  /// Index of the voxel containing a world point (m).
  Eigen::Vector3i voxel_of(const Vec3& world) const {
    return Eigen::Vector3i(static_cast<int>(std::floor(world.x() * inv_h_ + 0.5)),
                           static_cast<int>(std::floor(world.y() * inv_h_ + 0.5)),
                           static_cast<int>(std::floor(world.z() * inv_h_ + 0.5)));
  }
  /// World position of a voxel's centre (m).
  Vec3 centre_of(const Eigen::Vector3i& voxel) const { return h_ * voxel.cast<double>(); }

  /// Where a world point falls in the arrays, located once for both its
  /// state and its clearance (the pointshell's lookup reads both).
  struct Cell {
    bool inside = false;                          ///< within the arrays (else free)
    Eigen::Vector3i v = Eigen::Vector3i::Zero();  ///< voxel, relative to the arrays
    std::size_t block = 0;                        ///< index of its block
    int local = 0;                                ///< index within the block
  };
  /// The cell of the voxel containing a world point (m).
  Cell cell_at(const Vec3& world) const {
    Cell cell;
    const Vec3 u = world * inv_h_ + Vec3::Constant(0.5) - first_voxel_;
    // Compared before the cast (a far point's index would not fit an int;
    // NaN fails the test).
    cell.inside = u.x() >= 0 && u.y() >= 0 && u.z() >= 0 && u.x() < voxels_per_axis_.x() &&
                  u.y() < voxels_per_axis_.y() && u.z() < voxels_per_axis_.z();
    if (!cell.inside) return cell;
    // Truncation is the floor here: u ≥ 0.
    cell.v =
        Eigen::Vector3i(static_cast<int>(u.x()), static_cast<int>(u.y()), static_cast<int>(u.z()));
    cell.block = block_index(cell.v);
    cell.local = local_index(cell.v);
    return cell;
  }
  /// The cell of a voxel (index).
  Cell cell_of(const Eigen::Vector3i& voxel) const {
    Cell cell;
    cell.v = voxel - voxel_min_;
    cell.inside = inside(cell.v);
    if (!cell.inside) return cell;
    cell.block = block_index(cell.v);
    cell.local = local_index(cell.v);
    return cell;
  }
  /// The voxel (index) of a cell inside the arrays.
  Eigen::Vector3i voxel_of(const Cell& cell) const { return cell.v + voxel_min_; }
  /// State of a cell's voxel (free outside the arrays).
  VoxelState state(const Cell& cell) const {
    if (!cell.inside) return VoxelState::kFree;
    const int32_t code = block_code_[cell.block];
    if (code < 0) return static_cast<VoxelState>(-(code + 1));
    return static_cast<VoxelState>(
        states_[static_cast<std::size_t>(code) * kBlockVoxels + cell.local]);
  }
  /// State of a voxel (free outside the arrays).
  VoxelState state(const Eigen::Vector3i& voxel) const { return state(cell_of(voxel)); }
  /// clearance(world) for the cell of `world`.
  double clearance(const Cell& cell, const Vec3& world) const {
    if (!cell.inside) return clearance_outside(world);
    const int32_t code = clearance_code_[cell.block];
    if (code < 0) return (-code - 1) * kBlockEdge * h_;
    const int voxels = fine_[static_cast<std::size_t>(code) * kBlockVoxels + cell.local];
    return voxels <= 1 ? 0.0 : (voxels - 1) * h_;
  }

  /// Signed distance stored at a voxel centre (m, negative inside); the
  /// exterior band value outside the arrays. Only with distances.
  float distance(const Eigen::Vector3i& voxel) const {
    const Eigen::Vector3i v = voxel - voxel_min_;
    if (!inside(v)) return outside_distance_;
    const int32_t code = block_code_[block_index(v)];
    if (code < 0) return uniform_distance_[block_index(v)];
    return distances_[static_cast<std::size_t>(code) * kBlockVoxels + local_index(v)];
  }

  /// Trilinear interpolation of the voxel-centre distances at a world
  /// point (m) and its exact gradient (world, dimensionless). Only with distances.
  double interpolated_distance(const Vec3& world, Vec3& gradient) const;

  /// A lower bound (m) on the distance from a world point to any non-free
  /// voxel (the voxel's cube): (k − 1) h for a Chebyshev distance of k
  /// voxels near the scene, (k − 1)·8h for k blocks farther out.
  double clearance(const Vec3& world) const { return clearance(cell_at(world), world); }

  /// Bytes the arrays hold.
  int64_t memory_bytes() const;
  int64_t dense_blocks() const { return static_cast<int64_t>(states_.size() / kBlockVoxels); }
  /// Voxels per state over the arrays, indexed by VoxelState.
  std::vector<int64_t> state_counts() const;

 private:
  bool inside(const Eigen::Vector3i& v) const {
    return static_cast<unsigned>(v.x()) < static_cast<unsigned>(voxel_count_.x()) &&
           static_cast<unsigned>(v.y()) < static_cast<unsigned>(voxel_count_.y()) &&
           static_cast<unsigned>(v.z()) < static_cast<unsigned>(voxel_count_.z());
  }
  std::size_t block_index(const Eigen::Vector3i& v) const {
    return (static_cast<std::size_t>(v.x() >> kBlockLog2) * block_count_.y() +
            static_cast<std::size_t>(v.y() >> kBlockLog2)) *
               block_count_.z() +
           static_cast<std::size_t>(v.z() >> kBlockLog2);
  }
  static int local_index(const Eigen::Vector3i& v) {
    constexpr int mask = kBlockEdge - 1;
    return ((v.x() & mask) << (2 * kBlockLog2)) | ((v.y() & mask) << kBlockLog2) | (v.z() & mask);
  }
  double clearance_outside(const Vec3& world) const;
  void compute_block_clearance();
  void compute_fine_clearance();
  /// Sets clearance_code_ of every block and lists the blocks within
  /// kFineBlocks of a non-free one (block coordinates) with their non-free
  /// voxels as bits (word x, bit 8y + z), in block order.
  void find_near_blocks(std::vector<Eigen::Vector3i>& near,
                        std::vector<std::array<uint64_t, kBlockEdge>>& non_free);
  /// Per near block, the clearance codes of its six face neighbours
  /// (index 2 axis + side, side 0 towards −axis), −1 outside the arrays.
  std::vector<std::array<int32_t, 6>> face_neighbours(
      const std::vector<Eigen::Vector3i>& near) const;
  std::size_t block_index_of_block(const Eigen::Vector3i& b) const {
    return (static_cast<std::size_t>(b.x()) * block_count_.y() + static_cast<std::size_t>(b.y())) *
               block_count_.z() +
           static_cast<std::size_t>(b.z());
  }

  double h_ = 1;
  double inv_h_ = 1;
  bool with_distances_ = false;
  Eigen::Vector3i voxel_min_ = Eigen::Vector3i::Zero();    ///< first voxel of the arrays
  Eigen::Vector3i voxel_count_ = Eigen::Vector3i::Zero();  ///< voxels per axis
  Vec3 first_voxel_ = Vec3::Zero();      ///< voxel_min_, as doubles (converted once)
  Vec3 voxels_per_axis_ = Vec3::Zero();  ///< voxel_count_, as doubles
  Eigen::Vector3i block_count_ = Eigen::Vector3i::Zero();  ///< blocks per axis
  std::vector<int32_t> block_code_;  ///< >= 0: dense block number; < 0: uniform state −(code+1)
  std::vector<uint8_t> states_;      ///< kBlockVoxels per dense block
  std::vector<float> distances_;     ///< kBlockVoxels per dense block (with distances)
  std::vector<float> uniform_distance_;  ///< per block (with distances)
  std::vector<uint8_t> clearance_;       ///< per block, Chebyshev blocks to a non-free block
  /// Per block: its number in fine_ (within kFineBlocks of a non-free
  /// block), else minus its Chebyshev distance in blocks.
  std::vector<int32_t> clearance_code_;
  std::vector<uint8_t> fine_;   ///< kBlockVoxels per near block: Chebyshev voxels, capped
  float outside_distance_ = 0;  ///< m, read outside the arrays
};

}  // namespace hb
