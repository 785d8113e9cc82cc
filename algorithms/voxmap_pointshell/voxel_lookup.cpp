#include "algorithms/voxmap_pointshell/voxel_lookup.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <deque>
#include <limits>

namespace hb {

namespace {
constexpr uint8_t kUnreached = 255;

int32_t uniform_code(VoxelState state) { return -(static_cast<int32_t>(state) + 1); }

// std::floor(x), by truncation where x fits an int (without SSE4.1 the
// library's floor is a dozen instructions more).
inline double floor_of(double x) {
  if (!(std::abs(x) < 2147483647.0)) return std::floor(x);
  const double truncated = static_cast<double>(static_cast<int>(x));
  return truncated > x ? truncated - 1 : truncated;
}
}  // namespace

VoxelLookup::VoxelLookup(double voxel_size_m, const Eigen::Vector3i& block_min,
                         const Eigen::Vector3i& block_count, bool with_distances,
                         float outside_distance_m)
    : h_(voxel_size_m),
      inv_h_(1.0 / voxel_size_m),
      with_distances_(with_distances),
      voxel_min_(block_min * kBlockEdge),
      voxel_count_(block_count * kBlockEdge),
      first_voxel_(voxel_min_.cast<double>()),
      voxels_per_axis_(voxel_count_.cast<double>()),
      block_count_(block_count),
      outside_distance_(outside_distance_m) {
  const auto blocks = static_cast<std::size_t>(block_count.prod());
  block_code_.assign(blocks, uniform_code(VoxelState::kFree));
  if (with_distances_) uniform_distance_.assign(blocks, outside_distance_m);
  clearance_.assign(blocks, kUnreached);
  clearance_code_.assign(blocks, -static_cast<int32_t>(kUnreached));
}

void VoxelLookup::set_uniform_block(const Eigen::Vector3i& b, VoxelState state, float distance) {
  const std::size_t index = block_index_of_block(b);
  block_code_[index] = uniform_code(state);
  if (with_distances_) uniform_distance_[index] = distance;
}

void VoxelLookup::set_dense_block(const Eigen::Vector3i& b, const uint8_t* states,
                                  const float* distances) {
  const std::size_t index = block_index_of_block(b);
  const std::size_t number = states_.size() / kBlockVoxels;
  block_code_[index] = static_cast<int32_t>(number);
  states_.insert(states_.end(), states, states + kBlockVoxels);
  if (with_distances_) distances_.insert(distances_.end(), distances, distances + kBlockVoxels);
}

void VoxelLookup::finish() {
  compute_block_clearance();
  compute_fine_clearance();
}

void VoxelLookup::compute_block_clearance() {
  // Multi-source breadth-first search over the 26-neighbourhood: the number
  // of steps is the Chebyshev distance in blocks.
  std::deque<Eigen::Vector3i> queue;
  for (int x = 0; x < block_count_.x(); ++x) {
    for (int y = 0; y < block_count_.y(); ++y) {
      for (int z = 0; z < block_count_.z(); ++z) {
        const Eigen::Vector3i b(x, y, z);
        const std::size_t index = block_index_of_block(b);
        const int32_t code = block_code_[index];
        bool occupied = code != uniform_code(VoxelState::kFree);
        if (code >= 0) {
          const uint8_t* s = states_.data() + static_cast<std::size_t>(code) * kBlockVoxels;
          occupied = std::any_of(s, s + kBlockVoxels, [](uint8_t v) { return v != 0; });
        }
        clearance_[index] = occupied ? 0 : kUnreached;
        if (occupied) queue.push_back(b);
      }
    }
  }
  while (!queue.empty()) {
    const Eigen::Vector3i b = queue.front();
    queue.pop_front();
    const uint8_t next = static_cast<uint8_t>(clearance_[block_index_of_block(b)] + 1);
    if (next >= kUnreached) continue;
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = -1; dz <= 1; ++dz) {
          const Eigen::Vector3i n = b + Eigen::Vector3i(dx, dy, dz);
          if ((n.array() < 0).any() || (n.array() >= block_count_.array()).any()) continue;
          uint8_t& c = clearance_[block_index_of_block(n)];
          if (c > next) {
            c = next;
            queue.push_back(n);
          }
        }
      }
    }
  }
}

namespace {

// A block's voxels as bits: word x (0..7), bit 8y + z, so that the bit of
// voxel (x, y, z) is at local index (x << 6) | (y << 3) | z within the block.
using BlockBits = std::array<uint64_t, VoxelLookup::kBlockEdge>;
constexpr uint64_t kZFirst = 0x0101010101010101ULL;  // z = 0 of every (y) row
constexpr uint64_t kZLast = 0x8080808080808080ULL;   // z = 7
constexpr uint64_t kYFirst = 0xFFULL;                // y = 0
constexpr int kYLastShift = 56;                      // y = 7 starts at bit 56

// Per near block, the codes of its face neighbours (2 axis + side, side 0
// towards −axis), −1 where there is none.
using FaceNeighbours = std::vector<std::array<int32_t, 6>>;

// The bits of near block c's face neighbour along an axis, nullptr if none.
inline const BlockBits* face(const FaceNeighbours& faces, const std::vector<BlockBits>& bits,
                             std::size_t c, int axis, int side) {
  const int32_t n = faces[c][2 * axis + side];
  return n >= 0 ? &bits[static_cast<std::size_t>(n)] : nullptr;
}

// Dilates every near block's bits by one voxel along z, across block faces.
void dilate_along_z(const std::vector<BlockBits>& reached, const FaceNeighbours& faces,
                    std::vector<BlockBits>& along_z) {
  for (std::size_t c = 0; c < reached.size(); ++c) {
    const BlockBits& w = reached[c];
    const BlockBits* below = face(faces, reached, c, 2, 0);
    const BlockBits* above = face(faces, reached, c, 2, 1);
    for (int x = 0; x < VoxelLookup::kBlockEdge; ++x) {
      uint64_t d = w[x] | ((w[x] << 1) & ~kZFirst) | ((w[x] >> 1) & ~kZLast);
      if (below) d |= ((*below)[x] & kZLast) >> 7;
      if (above) d |= ((*above)[x] & kZFirst) << 7;
      along_z[c][x] = d;
    }
  }
}

// Dilates every near block's bits by one voxel along y, across block faces.
void dilate_along_y(const std::vector<BlockBits>& along_z, const FaceNeighbours& faces,
                    std::vector<BlockBits>& along_y) {
  for (std::size_t c = 0; c < along_z.size(); ++c) {
    const BlockBits& w = along_z[c];
    const BlockBits* below = face(faces, along_z, c, 1, 0);
    const BlockBits* above = face(faces, along_z, c, 1, 1);
    for (int x = 0; x < VoxelLookup::kBlockEdge; ++x) {
      uint64_t d = w[x] | (w[x] << 8) | (w[x] >> 8);
      if (below) d |= (*below)[x] >> kYLastShift;
      if (above) d |= ((*above)[x] & kYFirst) << kYLastShift;
      along_y[c][x] = d;
    }
  }
}

// Dilates every near block's bits by one voxel along x, across block faces,
// into `grown`, and gives the voxels it reaches first (not in `reached`)
// the Chebyshev distance `distance` in `fine`. Returns whether any was new.
bool dilate_along_x(const std::vector<BlockBits>& along_y, const FaceNeighbours& faces,
                    const std::vector<BlockBits>& reached, int distance,
                    std::vector<BlockBits>& grown, std::vector<uint8_t>& fine) {
  constexpr int kEdge = VoxelLookup::kBlockEdge;
  bool any = false;
  for (std::size_t c = 0; c < along_y.size(); ++c) {
    const BlockBits& w = along_y[c];
    const BlockBits* below = face(faces, along_y, c, 0, 0);
    const BlockBits* above = face(faces, along_y, c, 0, 1);
    for (int x = 0; x < kEdge; ++x) {
      uint64_t d = w[x];
      if (x > 0)
        d |= w[x - 1];
      else if (below)
        d |= (*below)[kEdge - 1];
      if (x < kEdge - 1)
        d |= w[x + 1];
      else if (above)
        d |= (*above)[0];
      grown[c][x] = d;
      // Voxels first reached by this dilation.
      for (uint64_t fresh = d & ~reached[c][x]; fresh != 0; fresh &= fresh - 1) {
        const int bit = __builtin_ctzll(fresh);
        fine[c * VoxelLookup::kBlockVoxels + static_cast<std::size_t>((x << 6) | bit)] =
            static_cast<uint8_t>(distance);
        any = true;
      }
    }
  }
  return any;
}

}  // namespace

void VoxelLookup::find_near_blocks(std::vector<Eigen::Vector3i>& near,
                                   std::vector<std::array<uint64_t, kBlockEdge>>& non_free) {
  for (int x = 0; x < block_count_.x(); ++x) {
    for (int y = 0; y < block_count_.y(); ++y) {
      for (int z = 0; z < block_count_.z(); ++z) {
        const Eigen::Vector3i b(x, y, z);
        const std::size_t index = block_index_of_block(b);
        if (clearance_[index] > kFineBlocks) {
          clearance_code_[index] = -static_cast<int32_t>(clearance_[index]);
          continue;
        }
        clearance_code_[index] = static_cast<int32_t>(near.size());
        near.push_back(b);
        BlockBits bits{};
        const int32_t code = block_code_[index];
        for (int n = 0; n < kBlockVoxels; ++n) {
          const bool non_free_voxel =
              code >= 0 ? states_[static_cast<std::size_t>(code) * kBlockVoxels + n] != 0
                        : code != uniform_code(VoxelState::kFree);
          if (non_free_voxel) bits[n >> 6] |= uint64_t{1} << (n & 63);
        }
        non_free.push_back(bits);
      }
    }
  }
}

std::vector<std::array<int32_t, 6>> VoxelLookup::face_neighbours(
    const std::vector<Eigen::Vector3i>& near) const {
  // The code of the face neighbour of near block c along an axis, −1 if none.
  const auto neighbour = [&](std::size_t c, int axis, int step) -> int32_t {
    Eigen::Vector3i b = near[c];
    b[axis] += step;
    if ((b.array() < 0).any() || (b.array() >= block_count_.array()).any()) return -1;
    return clearance_code_[block_index_of_block(b)];
  };
  FaceNeighbours faces(near.size());
  for (std::size_t c = 0; c < near.size(); ++c)
    for (int axis = 0; axis < 3; ++axis)
      for (int side = 0; side < 2; ++side)
        faces[c][2 * axis + side] = neighbour(c, axis, side == 0 ? -1 : 1);
  return faces;
}

void VoxelLookup::compute_fine_clearance() {
  // The set of voxels within Chebyshev distance k of a non-free voxel is the
  // non-free set dilated k times by the 3×3×3 cube, which is separable: one
  // voxel along z, then y, then x. Done on bit masks, block by block, over
  // the near blocks; a voxel gets k at the dilation that first reaches it.
  // Blocks farther than kFineBlocks are never reached within kFineCap steps
  // (and a dilation's intermediate voxels are within one voxel of what it
  // reaches), so leaving them out is exact. Voxels not reached keep kFineCap + 1.
  constexpr uint8_t kFar = kFineCap + 1;
  clearance_code_.assign(clearance_.size(), -1);
  fine_.clear();
  std::vector<Eigen::Vector3i> near;  // block coordinates of the near blocks, by code
  std::vector<BlockBits> reached;     // per near block
  find_near_blocks(near, reached);
  fine_.assign(near.size() * kBlockVoxels, kFar);
  for (std::size_t c = 0; c < near.size(); ++c)
    for (int n = 0; n < kBlockVoxels; ++n)
      if ((reached[c][n >> 6] >> (n & 63)) & 1) fine_[c * kBlockVoxels + n] = 0;

  const FaceNeighbours faces = face_neighbours(near);
  std::vector<BlockBits> along_z(near.size()), along_y(near.size()), grown(near.size());
  for (int distance = 1; distance <= kFineCap; ++distance) {
    dilate_along_z(reached, faces, along_z);
    dilate_along_y(along_z, faces, along_y);
    const bool any = dilate_along_x(along_y, faces, reached, distance, grown, fine_);
    reached.swap(grown);
    if (!any) break;
  }
}

double VoxelLookup::interpolated_distance(const Vec3& world, Vec3& gradient) const {
  const Vec3 u = world * inv_h_;
  const Vec3 base(floor_of(u.x()), floor_of(u.y()), floor_of(u.z()));
  const Vec3 f = u - base;
  const Eigen::Vector3i i0 = base.cast<int>();
  double c[2][2][2];
  const Eigen::Vector3i v = i0 - voxel_min_;
  constexpr int last = kBlockEdge - 1;
  const bool corners_inside = inside(v) && v.x() + 1 < voxel_count_.x() &&
                              v.y() + 1 < voxel_count_.y() && v.z() + 1 < voxel_count_.z();
  const int32_t code = corners_inside ? block_code_[block_index(v)] : -1;
  const bool one_block =
      corners_inside && (v.x() & last) != last && (v.y() & last) != last && (v.z() & last) != last;
  if (one_block && code < 0) {
    // All eight corners in one uniform block: the interpolation below would
    // give its distance exactly (c + f·0) and a zero gradient.
    gradient.setZero();
    return uniform_distance_[block_index(v)];
  }
  if (one_block) {
    // All eight corners in one dense block: x, y, z steps are 64, 8, 1.
    const float* corner =
        distances_.data() + static_cast<std::size_t>(code) * kBlockVoxels + local_index(v);
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b)
        for (int d = 0; d < 2; ++d)
          c[a][b][d] = corner[(a << (2 * kBlockLog2)) + (b << kBlockLog2) + d];
  } else if (corners_inside) {
    // The corners span up to two blocks along each axis: per axis, each
    // corner's block coordinate and place in the block.
    std::size_t block[3][2];
    int local[3][2];
    for (int axis = 0; axis < 3; ++axis) {
      for (int side = 0; side < 2; ++side) {
        const int w = v[axis] + side;
        block[axis][side] = static_cast<std::size_t>(w >> kBlockLog2);
        local[axis][side] = w & last;
      }
    }
    const auto rows = static_cast<std::size_t>(block_count_.y());
    const auto layers = static_cast<std::size_t>(block_count_.z());
    for (int a = 0; a < 2; ++a) {
      for (int b = 0; b < 2; ++b) {
        const std::size_t column = (block[0][a] * rows + block[1][b]) * layers;
        const int offset = (local[0][a] << (2 * kBlockLog2)) | (local[1][b] << kBlockLog2);
        for (int d = 0; d < 2; ++d) {
          const std::size_t index = column + block[2][d];
          const int32_t corner_code = block_code_[index];
          c[a][b][d] = corner_code < 0
                           ? uniform_distance_[index]
                           : distances_[static_cast<std::size_t>(corner_code) * kBlockVoxels +
                                        static_cast<std::size_t>(offset | local[2][d])];
        }
      }
    }
  } else {
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b)
        for (int d = 0; d < 2; ++d) c[a][b][d] = distance(i0 + Eigen::Vector3i(a, b, d));
  }
  // Interpolate along z, then y, then x, keeping the partial derivatives.
  double cz[2][2], dcz[2][2];
  for (int a = 0; a < 2; ++a) {
    for (int b = 0; b < 2; ++b) {
      cz[a][b] = c[a][b][0] + f.z() * (c[a][b][1] - c[a][b][0]);
      dcz[a][b] = c[a][b][1] - c[a][b][0];
    }
  }
  double cy[2], dcy_dy[2], dcy_dz[2];
  for (int a = 0; a < 2; ++a) {
    cy[a] = cz[a][0] + f.y() * (cz[a][1] - cz[a][0]);
    dcy_dy[a] = cz[a][1] - cz[a][0];
    dcy_dz[a] = dcz[a][0] + f.y() * (dcz[a][1] - dcz[a][0]);
  }
  const double value = cy[0] + f.x() * (cy[1] - cy[0]);
  gradient = Vec3(cy[1] - cy[0], dcy_dy[0] + f.x() * (dcy_dy[1] - dcy_dy[0]),
                  dcy_dz[0] + f.x() * (dcy_dz[1] - dcy_dz[0])) *
             inv_h_;
  return value;
}

double VoxelLookup::clearance_outside(const Vec3& world) const {
  if (!world.allFinite() || fine_.empty()) return std::numeric_limits<double>::infinity();
  // Every non-free voxel lies inside the arrays' box.
  const Vec3 low = h_ * (voxel_min_.cast<double>().array() - 0.5).matrix();
  const Vec3 high = low + h_ * voxel_count_.cast<double>();
  const Vec3 outside = (low - world).cwiseMax(world - high).cwiseMax(0.0);
  return outside.norm();  // 0 on the box's boundary
}

int64_t VoxelLookup::memory_bytes() const {
  return static_cast<int64_t>(block_code_.size() * sizeof(int32_t) + states_.size() +
                              distances_.size() * sizeof(float) +
                              uniform_distance_.size() * sizeof(float) + clearance_.size() +
                              clearance_code_.size() * sizeof(int32_t) + fine_.size());
}

std::vector<int64_t> VoxelLookup::state_counts() const {
  std::vector<int64_t> counts(4, 0);
  for (const int32_t code : block_code_) {
    if (code < 0) {
      counts[static_cast<std::size_t>(-(code + 1))] += kBlockVoxels;
    } else {
      const uint8_t* s = states_.data() + static_cast<std::size_t>(code) * kBlockVoxels;
      for (int k = 0; k < kBlockVoxels; ++k) ++counts[s[k]];
    }
  }
  return counts;
}

}  // namespace hb
