#include "harness/reference/surface_samples.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_set>

namespace hb {

namespace {
// Cell of a point on a grid of side `cell`, packed into 64 bits (21 bits per
// axis, ample for a tool of any practical size at any sensible spacing).
uint64_t cell_key(const Vec3& p, double cell) {
  auto axis = [&](double x) {
    return static_cast<uint64_t>(static_cast<int64_t>(std::floor(x / cell)) & 0x1fffff);
  };
  return axis(p.x()) | (axis(p.y()) << 21) | (axis(p.z()) << 42);
}
}  // namespace

std::vector<Vec3> sample_surface(const TriangleMesh& mesh, double spacing_m) {
  std::vector<Vec3> samples;
  std::unordered_set<uint64_t> taken;
  auto offer = [&](const Vec3& p) {
    if (taken.insert(cell_key(p, spacing_m)).second) samples.push_back(p);
  };
  for (const Vec3& v : mesh.vertices) offer(v);
  const double step = 0.5 * spacing_m;
  for (const auto& t : mesh.triangles) {
    const Vec3& a = mesh.vertices[t[0]];
    const Vec3& b = mesh.vertices[t[1]];
    const Vec3& c = mesh.vertices[t[2]];
    const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
    const int n = static_cast<int>(std::ceil(longest / step));
    if (n <= 1) continue;  // the vertices already cover it
    for (int i = 0; i <= n; ++i) {
      for (int j = 0; i + j <= n; ++j) {
        const double u = static_cast<double>(i) / n, v = static_cast<double>(j) / n;
        offer(a + u * (b - a) + v * (c - a));
      }
    }
  }
  return samples;
}

}  // namespace hb
