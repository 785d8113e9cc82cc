#include "algorithms/ccd/sphere_tree.h"

#include <algorithm>
#include <cmath>

#include "algorithms/ccd/interval.h"

namespace hb {

namespace {

/// The sphere about the centre of the vertices' bounding box. The computed
/// distance |v − c| is within a few rounding errors (relative 2^-53 each) of
/// the true one; 1e-12 relative and one ulp more make the radius an upper
/// bound with a wide margin. Squares below 1e-290 may have lost relative
/// accuracy to underflow: then the sum of the coordinate distances, which is
/// at least the distance, bounds it instead.
void enclose(std::span<const Vec3> vertices, std::span<const std::array<int, 3>> triangles,
             std::span<const int> members, SphereTreeNode& node) {
  Eigen::AlignedBox3d box;
  for (const int t : members)
    for (const int v : triangles[static_cast<std::size_t>(t)])
      box.extend(vertices[static_cast<std::size_t>(v)]);
  node.centre = box.center();
  double largest_squared = 0, largest_sum = 0;
  for (const int t : members)
    for (const int v : triangles[static_cast<std::size_t>(t)]) {
      const Vec3 d = vertices[static_cast<std::size_t>(v)] - node.centre;
      largest_squared = std::max(largest_squared, d.squaredNorm());
      largest_sum = std::max(largest_sum, d.cwiseAbs().sum());
    }
  const double distance = largest_squared < 1e-290 ? largest_sum : std::sqrt(largest_squared);
  node.radius = next_up(distance * (1 + 1e-12));
}

}  // namespace

SphereTree::SphereTree(std::span<const Vec3> vertices,
                       std::span<const std::array<int, 3>> triangles) {
  if (triangles.empty()) return;
  const std::size_t n = triangles.size();
  std::vector<Vec3> centroids(n);
  for (std::size_t t = 0; t < n; ++t) {
    const auto& tri = triangles[t];
    centroids[t] =
        (vertices[static_cast<std::size_t>(tri[0])] + vertices[static_cast<std::size_t>(tri[1])] +
         vertices[static_cast<std::size_t>(tri[2])]) /
        3.0;
  }
  triangle_order_.resize(n);
  for (std::size_t t = 0; t < n; ++t) triangle_order_[t] = static_cast<int>(t);
  nodes_.reserve(n);

  struct Pending {
    int node, begin, end;  // a node and its range of triangle_order_
  };
  std::vector<Pending> pending{{0, 0, static_cast<int>(n)}};
  nodes_.emplace_back();
  while (!pending.empty()) {
    const Pending job = pending.back();
    pending.pop_back();
    const auto members = std::span<int>(triangle_order_)
                             .subspan(static_cast<std::size_t>(job.begin),
                                      static_cast<std::size_t>(job.end - job.begin));
    enclose(vertices, triangles, members, nodes_[static_cast<std::size_t>(job.node)]);
    if (job.end - job.begin <= kMaxLeafTriangles) {
      nodes_[static_cast<std::size_t>(job.node)].first = job.begin;
      nodes_[static_cast<std::size_t>(job.node)].count = job.end - job.begin;
      continue;
    }
    Eigen::AlignedBox3d centroid_box;
    for (const int t : members) centroid_box.extend(centroids[static_cast<std::size_t>(t)]);
    int axis = 0;
    centroid_box.sizes().maxCoeff(&axis);
    const int middle = job.begin + (job.end - job.begin) / 2;
    std::nth_element(triangle_order_.begin() + job.begin, triangle_order_.begin() + middle,
                     triangle_order_.begin() + job.end, [&](int a, int b) {
                       return centroids[static_cast<std::size_t>(a)][axis] <
                              centroids[static_cast<std::size_t>(b)][axis];
                     });
    const int first_child = static_cast<int>(nodes_.size());
    nodes_[static_cast<std::size_t>(job.node)].first = first_child;
    nodes_[static_cast<std::size_t>(job.node)].count = 0;
    nodes_.emplace_back();
    nodes_.emplace_back();
    pending.push_back({first_child + 1, middle, job.end});
    pending.push_back({first_child, job.begin, middle});
  }
}

}  // namespace hb
