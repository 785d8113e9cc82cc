#include "algorithms/core/triangle_mesh.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <unordered_map>

#include "algorithms/core/input_error.h"

namespace hb {

Vec3 TriangleMesh::face_normal(std::size_t t) const {
  const auto& [i, j, k] = triangles[t];
  const Vec3 n = (vertices[j] - vertices[i]).cross(vertices[k] - vertices[i]);
  const double length = n.norm();
  // The negated test also rejects NaN lengths.
  if (!(length > 0.0)) return Vec3::Zero();
  return n / length;
}

Eigen::AlignedBox3d TriangleMesh::bounds() const {
  Eigen::AlignedBox3d box;  // starts empty
  for (const Vec3& v : vertices) box.extend(v);
  return box;
}

double TriangleMesh::radius_about(const Vec3& centre) const {
  double squared = 0.0;
  for (const Vec3& v : vertices) squared = std::max(squared, (v - centre).squaredNorm());
  return std::sqrt(squared);
}

namespace {

std::string triangle_location(std::size_t t) { return "triangle " + std::to_string(t); }

std::string edge_location(int a, int b) {
  return "edge (" + std::to_string(a) + ", " + std::to_string(b) + ")";
}

// Key of an undirected edge: the smaller index in the high 32 bits.
uint64_t edge_key(int a, int b) {
  const auto lo = static_cast<uint32_t>(std::min(a, b));
  const auto hi = static_cast<uint32_t>(std::max(a, b));
  return (static_cast<uint64_t>(lo) << 32) | hi;
}

// Mixes a 64-bit key so that keys built from small integers spread over the
// buckets (splitmix64 finaliser).
struct MixedHash {
  std::size_t operator()(uint64_t x) const {
    x ^= x >> 30;
    x *= 0xbf58476d1ce4e5b9ULL;
    x ^= x >> 27;
    x *= 0x94d049bb133111ebULL;
    x ^= x >> 31;
    return static_cast<std::size_t>(x);
  }
};

// Key of a triangle's vertex set; duplicates in any order or winding share it.
struct TriangleKey {
  std::array<int, 3> sorted;
  bool operator==(const TriangleKey&) const = default;
};
struct TriangleKeyHash {
  std::size_t operator()(const TriangleKey& key) const {
    const MixedHash mix;
    std::size_t h = mix(static_cast<uint32_t>(key.sorted[0]));
    h = mix(h ^ static_cast<uint32_t>(key.sorted[1]));
    return mix(h ^ static_cast<uint32_t>(key.sorted[2]));
  }
};

// How the triangles use one undirected edge.
struct EdgeUse {
  int count = 0;
  int first_triangle = -1;
  int second_triangle = -1;
  int third_triangle = -1;
  // Number of uses traversing the edge from the smaller to the larger index.
  int forward = 0;
};

std::string format_vertex(const Vec3& v) {
  std::ostringstream out;
  out << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return out.str();
}

std::string format_number(double x) {
  std::ostringstream out;
  out << x;
  return out.str();
}

std::optional<MeshDefect> find_index_defect(const TriangleMesh& mesh) {
  const auto vertex_count = static_cast<long long>(mesh.vertices.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int corner = 0; corner < 3; ++corner) {
      const int index = mesh.triangles[t][corner];
      if (index < 0 || index >= vertex_count) {
        return MeshDefect{triangle_location(t),
                          "vertex index " + std::to_string(index) + " (corner " +
                              std::to_string(corner) + ") is out of range; expected 0.." +
                              std::to_string(vertex_count - 1) + " for " +
                              std::to_string(vertex_count) + " vertices"};
      }
    }
  }
  return std::nullopt;
}

std::optional<MeshDefect> find_vertex_defect(const TriangleMesh& mesh) {
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    if (!mesh.vertices[v].allFinite()) {
      return MeshDefect{"vertex " + std::to_string(v),
                        "coordinates " + format_vertex(mesh.vertices[v]) +
                            " are not finite; expected finite numbers"};
    }
  }
  return std::nullopt;
}

// Zero area is judged relative to the mesh's size, so that a millimetre
// model and a kilometre model are held to the same standard.
std::optional<MeshDefect> find_degenerate_triangle(const TriangleMesh& mesh) {
  const double diagonal = mesh.bounds().diagonal().norm();
  const double min_area = 1e-12 * diagonal * diagonal;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& [i, j, k] = mesh.triangles[t];
    if (i == j || j == k || k == i) {
      const int repeated = (i == j || i == k) ? i : j;
      return MeshDefect{triangle_location(t), "repeats vertex " + std::to_string(repeated) +
                                                  "; a triangle needs three distinct vertices"};
    }
    const Vec3& a = mesh.vertices[i];
    const double area =
        0.5 * (mesh.vertices[j] - a).cross(mesh.vertices[k] - a).norm();
    if (!(area >= min_area)) {
      return MeshDefect{triangle_location(t),
                        "has zero area (" + format_number(area) + " m^2); expected at least " +
                            format_number(min_area) + " m^2 (1e-12 of the squared bounding-box "
                            "diagonal)"};
    }
  }
  return std::nullopt;
}

std::optional<MeshDefect> find_duplicate_triangle(const TriangleMesh& mesh) {
  std::unordered_map<TriangleKey, std::size_t, TriangleKeyHash> first_with_vertices;
  first_with_vertices.reserve(mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    TriangleKey key{mesh.triangles[t]};
    std::sort(key.sorted.begin(), key.sorted.end());
    const auto [it, inserted] = first_with_vertices.try_emplace(key, t);
    if (!inserted) {
      return MeshDefect{triangle_location(t),
                        "duplicates triangle " + std::to_string(it->second) + " (vertices " +
                            std::to_string(key.sorted[0]) + ", " + std::to_string(key.sorted[1]) +
                            ", " + std::to_string(key.sorted[2]) +
                            "); expected each triangle once"};
    }
  }
  return std::nullopt;
}

// Closedness, manifoldness and orientation from one pass over the edges.
// Edges are reported in the order the triangles first use them, so the
// answer does not depend on the hash map's iteration order.
std::optional<MeshDefect> find_edge_defect(const TriangleMesh& mesh) {
  std::unordered_map<uint64_t, EdgeUse, MixedHash> uses;
  uses.reserve(mesh.triangles.size() * 3 / 2 + 1);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int corner = 0; corner < 3; ++corner) {
      const int a = mesh.triangles[t][corner];
      const int b = mesh.triangles[t][(corner + 1) % 3];
      EdgeUse& use = uses[edge_key(a, b)];
      const int triangle = static_cast<int>(t);
      if (use.count == 0) use.first_triangle = triangle;
      if (use.count == 1) use.second_triangle = triangle;
      if (use.count == 2) use.third_triangle = triangle;
      ++use.count;
      if (a < b) ++use.forward;
    }
  }

  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int corner = 0; corner < 3; ++corner) {
      const int a = std::min(mesh.triangles[t][corner], mesh.triangles[t][(corner + 1) % 3]);
      const int b = std::max(mesh.triangles[t][corner], mesh.triangles[t][(corner + 1) % 3]);
      const EdgeUse& use = uses.at(edge_key(a, b));
      if (use.count == 1) {
        return MeshDefect{edge_location(a, b),
                          "open boundary: edge used by 1 triangle (triangle " +
                              std::to_string(use.first_triangle) + "), a closed mesh needs 2"};
      }
      if (use.count > 2) {
        return MeshDefect{edge_location(a, b),
                          "non-manifold: edge used by " + std::to_string(use.count) +
                              " triangles (" + std::to_string(use.first_triangle) + ", " +
                              std::to_string(use.second_triangle) + ", " +
                              std::to_string(use.third_triangle) +
                              (use.count > 3 ? ", ..." : "") + "), a closed mesh needs exactly 2"};
      }
      if (use.forward != 1) {
        const int from = use.forward == 2 ? a : b;
        const int to = use.forward == 2 ? b : a;
        return MeshDefect{edge_location(a, b),
                          "inconsistent orientation: triangles " +
                              std::to_string(use.first_triangle) + " and " +
                              std::to_string(use.second_triangle) + " both traverse it from " +
                              std::to_string(from) + " to " + std::to_string(to) +
                              "; triangles sharing an edge must traverse it in opposite "
                              "directions"};
      }
    }
  }
  return std::nullopt;
}

std::optional<MeshDefect> find_orientation_defect(const TriangleMesh& mesh) {
  // Tetrahedra from the bounding-box centre rather than the origin, so that a
  // mesh far from its origin does not lose the volume to cancellation.
  const Vec3 origin = mesh.bounds().center();
  double six_volume = 0.0;
  for (const auto& [i, j, k] : mesh.triangles) {
    six_volume += (mesh.vertices[i] - origin)
                      .dot((mesh.vertices[j] - origin).cross(mesh.vertices[k] - origin));
  }
  const double volume = six_volume / 6.0;
  if (!(volume > 0.0)) {
    return MeshDefect{"mesh", "mesh is inside-out: normals point inward (enclosed volume " +
                                  format_number(volume) +
                                  " m^3); expected triangles counter-clockwise seen from "
                                  "outside, enclosing a positive volume"};
  }
  return std::nullopt;
}

}  // namespace

std::optional<MeshDefect> find_mesh_defect(const TriangleMesh& mesh) {
  if (mesh.vertices.empty() || mesh.triangles.empty()) {
    return MeshDefect{"mesh", "mesh is empty (" + std::to_string(mesh.vertices.size()) +
                                  " vertices, " + std::to_string(mesh.triangles.size()) +
                                  " triangles); a closed mesh needs at least 4 triangles"};
  }
  // Each check relies on the ones before it: indices in range before
  // coordinates are read, finite coordinates before areas, distinct
  // vertices before edges are counted, a closed consistent surface before
  // its volume means anything.
  if (auto defect = find_index_defect(mesh)) return defect;
  if (auto defect = find_vertex_defect(mesh)) return defect;
  if (auto defect = find_degenerate_triangle(mesh)) return defect;
  if (auto defect = find_duplicate_triangle(mesh)) return defect;
  if (auto defect = find_edge_defect(mesh)) return defect;
  return find_orientation_defect(mesh);
}

void require_valid_mesh(const TriangleMesh& mesh, const std::string& source) {
  if (auto defect = find_mesh_defect(mesh)) {
    throw InputError(source, defect->location, defect->message);
  }
}

TriangleMesh transformed(const TriangleMesh& mesh, const Pose& pose) {
  TriangleMesh result;
  result.triangles = mesh.triangles;
  result.vertices.reserve(mesh.vertices.size());
  for (const Vec3& v : mesh.vertices) result.vertices.push_back(pose.transform_point(v));
  return result;
}

}  // namespace hb
