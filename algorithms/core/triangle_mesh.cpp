#include "hapticbench/triangle_mesh.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>

#include "hapticbench/input_error.h"

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

// Key of an undirected edge: the smaller index in the high 32 bits. Never
// all ones, since indices are below 2^31.
uint64_t edge_key(int a, int b) {
  const auto lo = static_cast<uint32_t>(std::min(a, b));
  const auto hi = static_cast<uint32_t>(std::max(a, b));
  return (static_cast<uint64_t>(lo) << 32) | hi;
}

// Hash table from 64-bit keys to dense ids 0, 1, 2, ... in order of first
// insertion (open addressing, linear probing): one flat allocation instead
// of std::unordered_map's node per key, several times faster on meshes of
// 100k triangles and more.
class DenseIdTable {
 public:
  explicit DenseIdTable(std::size_t expected_keys) {
    std::size_t capacity = 16;
    while (capacity < 2 * expected_keys) capacity *= 2;
    keys_.assign(capacity, kEmpty);
    ids_.resize(capacity);
    mask_ = capacity - 1;
  }
  /// The key's id, and whether this call inserted it. key must not be kEmpty.
  std::pair<int, bool> insert(uint64_t key) {
    for (std::size_t slot = mix(key) & mask_;; slot = (slot + 1) & mask_) {
      if (keys_[slot] == key) return {ids_[slot], false};
      if (keys_[slot] == kEmpty) {
        keys_[slot] = key;
        ids_[slot] = size_++;
        return {ids_[slot], true};
      }
    }
  }
  static constexpr uint64_t kEmpty = ~uint64_t{0};

 private:
  // splitmix64 finaliser: spreads keys built from small integers.
  static std::size_t mix(uint64_t x) {
    x ^= x >> 30;
    x *= 0xbf58476d1ce4e5b9ULL;
    x ^= x >> 27;
    x *= 0x94d049bb133111ebULL;
    x ^= x >> 31;
    return static_cast<std::size_t>(x);
  }
  std::vector<uint64_t> keys_;
  std::vector<int> ids_;
  std::size_t mask_ = 0;
  int size_ = 0;
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

// Every undirected edge once, and which edge each triangle corner starts.
struct EdgeIncidence {
  std::vector<EdgeUse> edges;
  std::vector<int> edge_of_corner;  // [3 t + corner]: edge from corner to corner + 1
};

EdgeIncidence build_edge_incidence(const TriangleMesh& mesh) {
  EdgeIncidence incidence;
  DenseIdTable ids(mesh.triangles.size() * 3 / 2);
  incidence.edges.reserve(mesh.triangles.size() * 3 / 2);
  incidence.edge_of_corner.resize(mesh.triangles.size() * 3);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int corner = 0; corner < 3; ++corner) {
      const int a = mesh.triangles[t][corner];
      const int b = mesh.triangles[t][(corner + 1) % 3];
      const auto [id, inserted] = ids.insert(edge_key(a, b));
      if (inserted) incidence.edges.emplace_back();
      incidence.edge_of_corner[3 * t + corner] = id;
      EdgeUse& use = incidence.edges[id];
      const int triangle = static_cast<int>(t);
      if (use.count == 0) use.first_triangle = triangle;
      if (use.count == 1) use.second_triangle = triangle;
      if (use.count == 2) use.third_triangle = triangle;
      ++use.count;
      if (a < b) ++use.forward;
    }
  }
  return incidence;
}

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
        return MeshDefect{triangle_location(t), "vertex index " + std::to_string(index) +
                                                    " (corner " + std::to_string(corner) +
                                                    ") is out of range; expected 0.." +
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
    const double area = 0.5 * (mesh.vertices[j] - a).cross(mesh.vertices[k] - a).norm();
    if (!(area >= min_area)) {
      return MeshDefect{triangle_location(t), "has zero area (" + format_number(area) +
                                                  " m^2); expected at least " +
                                                  format_number(min_area) +
                                                  " m^2 (1e-12 of the squared bounding-box "
                                                  "diagonal)"};
    }
  }
  return std::nullopt;
}

// Two triangles with the same vertex set {a < b < c} share the edge (a, b)
// and the vertex c, so (id of edge (a, b), c) identifies the set in 64 bits.
std::optional<MeshDefect> find_duplicate_triangle(const TriangleMesh& mesh,
                                                  const EdgeIncidence& incidence) {
  DenseIdTable ids(mesh.triangles.size());
  std::vector<std::size_t> triangle_of_id;
  triangle_of_id.reserve(mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    std::array<int, 3> sorted = mesh.triangles[t];
    std::sort(sorted.begin(), sorted.end());
    // The corner whose edge joins the two smallest indices is the one
    // opposite the largest.
    int corner = 0;
    while (mesh.triangles[t][(corner + 2) % 3] != sorted[2]) ++corner;
    const auto edge = static_cast<uint32_t>(incidence.edge_of_corner[3 * t + corner]);
    const auto [id, inserted] =
        ids.insert((static_cast<uint64_t>(edge) << 32) | static_cast<uint32_t>(sorted[2]));
    if (inserted) {
      triangle_of_id.push_back(t);
      continue;
    }
    return MeshDefect{triangle_location(t),
                      "duplicates triangle " + std::to_string(triangle_of_id[id]) + " (vertices " +
                          std::to_string(sorted[0]) + ", " + std::to_string(sorted[1]) + ", " +
                          std::to_string(sorted[2]) + "); expected each triangle once"};
  }
  return std::nullopt;
}

// Closedness, manifoldness and orientation. Edges are reported in the
// order the triangles first use them, so the answer does not depend on how
// the edges were numbered.
std::optional<MeshDefect> find_edge_defect(const TriangleMesh& mesh,
                                           const EdgeIncidence& incidence) {
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int corner = 0; corner < 3; ++corner) {
      const int a = std::min(mesh.triangles[t][corner], mesh.triangles[t][(corner + 1) % 3]);
      const int b = std::max(mesh.triangles[t][corner], mesh.triangles[t][(corner + 1) % 3]);
      const EdgeUse& use = incidence.edges[incidence.edge_of_corner[3 * t + corner]];
      if (use.count == 1) {
        return MeshDefect{edge_location(a, b), "open boundary: edge used by 1 triangle (triangle " +
                                                   std::to_string(use.first_triangle) +
                                                   "), a closed mesh needs 2"};
      }
      if (use.count > 2) {
        return MeshDefect{edge_location(a, b),
                          "non-manifold: edge used by " + std::to_string(use.count) +
                              " triangles (" + std::to_string(use.first_triangle) + ", " +
                              std::to_string(use.second_triangle) + ", " +
                              std::to_string(use.third_triangle) + (use.count > 3 ? ", ..." : "") +
                              "), a closed mesh needs exactly 2"};
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

std::optional<MeshDefect> find_mesh_defect(const TriangleMesh& mesh, MeshRequirement requirement) {
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
  const EdgeIncidence incidence = build_edge_incidence(mesh);
  if (auto defect = find_duplicate_triangle(mesh, incidence)) return defect;
  if (requirement == MeshRequirement::kSurface) return std::nullopt;
  if (auto defect = find_edge_defect(mesh, incidence)) return defect;
  return find_orientation_defect(mesh);
}

void require_valid_mesh(const TriangleMesh& mesh, const std::string& source,
                        MeshRequirement requirement) {
  if (auto defect = find_mesh_defect(mesh, requirement)) {
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
