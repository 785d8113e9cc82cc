#include "hapticbench/shapes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <sstream>
#include <unordered_map>

#include "hapticbench/input_error.h"

namespace hb {

std::string shape_type_name(ShapeType type) {
  switch (type) {
    case ShapeType::kBox:
      return "box";
    case ShapeType::kSphere:
      return "sphere";
    case ShapeType::kCapsule:
      return "capsule";
    case ShapeType::kBoxWithHole:
      return "box_with_hole";
  }
  return "unknown";
}

namespace {

// Finer meshes than this are millions of triangles: more than any haptic
// scene needs, and a likely typo.
constexpr int kMaxSubdivisions = 7;

std::string format_number(double x) {
  std::ostringstream out;
  out << x;
  return out.str();
}

void require_positive(double value, const std::string& field) {
  if (!std::isfinite(value) || value <= 0.0)
    throw InputError("", field,
                     "expected a positive length in metres, got " + format_number(value));
}

void require_subdivisions(int subdivisions) {
  if (subdivisions < 0 || subdivisions > kMaxSubdivisions)
    throw InputError("", "shape.subdivisions",
                     "expected a whole number in [0, " + std::to_string(kMaxSubdivisions) +
                         "], got " + std::to_string(subdivisions));
}

void require_valid_shape(const Shape& shape) {
  switch (shape.type) {
    case ShapeType::kBox:
      for (int axis = 0; axis < 3; ++axis) require_positive(shape.size[axis], "shape.size");
      return;
    case ShapeType::kSphere:
      require_positive(shape.radius, "shape.radius");
      require_subdivisions(shape.subdivisions);
      return;
    case ShapeType::kCapsule:
      require_positive(shape.radius, "shape.radius");
      if (!std::isfinite(shape.length) || shape.length < 0.0)
        throw InputError("", "shape.length",
                         "expected a length >= 0 in metres, got " + format_number(shape.length));
      require_subdivisions(shape.subdivisions);
      return;
    case ShapeType::kBoxWithHole:
      for (int axis = 0; axis < 3; ++axis) require_positive(shape.size[axis], "shape.size");
      for (int axis = 0; axis < 2; ++axis) {
        require_positive(shape.hole_size[axis], "shape.hole_size");
        if (shape.hole_size[axis] >= shape.size[axis])
          throw InputError("", "shape.hole_size",
                           "expected the hole (" + format_number(shape.hole_size[axis]) +
                               " m) narrower than the box (" + format_number(shape.size[axis]) +
                               " m) along " + std::string(1, "xy"[axis]));
      }
      return;
  }
  throw InputError("", "shape.type", "unknown shape type");
}

// Collects vertices and triangles; quads are given as a cycle of corners and
// the direction they face, so every face comes out counter-clockwise seen
// from outside without hand-ordering each one.
class MeshBuilder {
 public:
  int add_vertex(const Vec3& v) {
    mesh_.vertices.push_back(v);
    return static_cast<int>(mesh_.vertices.size()) - 1;
  }
  void add_triangle(int a, int b, int c) { mesh_.triangles.push_back({a, b, c}); }
  /// A planar quad a-b-c-d (in cyclic order, either sense) facing `outward`.
  void add_quad(int a, int b, int c, int d, const Vec3& outward) {
    const auto& v = mesh_.vertices;
    if ((v[b] - v[a]).cross(v[c] - v[a]).dot(outward) < 0.0) std::swap(b, d);
    add_triangle(a, b, c);
    add_triangle(a, c, d);
  }
  TriangleMesh take() { return std::move(mesh_); }

 private:
  TriangleMesh mesh_;
};

TriangleMesh box_mesh(const Vec3& size) {
  MeshBuilder builder;
  // Corner index bits: x, y, z; a set bit means the + side.
  std::array<int, 8> corner;
  for (int i = 0; i < 8; ++i) {
    corner[i] = builder.add_vertex(0.5 * Vec3((i & 1) ? size.x() : -size.x(),
                                              (i & 2) ? size.y() : -size.y(),
                                              (i & 4) ? size.z() : -size.z()));
  }
  for (int axis = 0; axis < 3; ++axis) {
    const int u = 1 << ((axis + 1) % 3);
    const int v = 1 << ((axis + 2) % 3);
    for (int side = 0; side < 2; ++side) {
      const int base = side ? (1 << axis) : 0;
      const Vec3 outward = (side ? 1.0 : -1.0) * Vec3::Unit(axis);
      builder.add_quad(corner[base], corner[base + u], corner[base + u + v], corner[base + v],
                       outward);
    }
  }
  return builder.take();
}

// Icosahedron refined `subdivisions` times by splitting every triangle into
// four and pushing the new vertices onto the sphere.
TriangleMesh sphere_mesh(double radius, int subdivisions) {
  const double phi = 0.5 * (1.0 + std::sqrt(5.0));
  TriangleMesh mesh;
  mesh.vertices = {{-1, phi, 0}, {1, phi, 0}, {-1, -phi, 0}, {1, -phi, 0},
                   {0, -1, phi}, {0, 1, phi}, {0, -1, -phi}, {0, 1, -phi},
                   {phi, 0, -1}, {phi, 0, 1}, {-phi, 0, -1}, {-phi, 0, 1}};
  for (Vec3& v : mesh.vertices) v.normalize();
  mesh.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                    {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                    {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                    {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};

  for (int level = 0; level < subdivisions; ++level) {
    std::unordered_map<uint64_t, int> midpoint_of_edge;
    midpoint_of_edge.reserve(mesh.triangles.size() * 3 / 2);
    auto midpoint = [&](int a, int b) {
      const uint64_t key =
          (static_cast<uint64_t>(std::min(a, b)) << 32) | static_cast<uint32_t>(std::max(a, b));
      const auto [it, inserted] =
          midpoint_of_edge.try_emplace(key, static_cast<int>(mesh.vertices.size()));
      if (inserted) mesh.vertices.push_back((mesh.vertices[a] + mesh.vertices[b]).normalized());
      return it->second;
    };
    std::vector<std::array<int, 3>> finer;
    finer.reserve(mesh.triangles.size() * 4);
    for (const auto& [a, b, c] : mesh.triangles) {
      const int ab = midpoint(a, b);
      const int bc = midpoint(b, c);
      const int ca = midpoint(c, a);
      finer.push_back({a, ab, ca});
      finer.push_back({b, bc, ab});
      finer.push_back({c, ca, bc});
      finer.push_back({ab, bc, ca});
    }
    mesh.triangles = std::move(finer);
  }
  for (Vec3& v : mesh.vertices) v *= radius;
  return mesh;
}

// Latitude rings on two hemispherical caps (2^subdivisions bands each, from
// pole to equator) joined by the cylinder, 4 · 2^subdivisions vertices per
// ring. Every vertex lies on the capsule, so the mesh is inscribed.
TriangleMesh capsule_mesh(double radius, double length, int subdivisions) {
  const int bands = 1 << subdivisions;
  const int segments = 4 * bands;
  const double half_length = 0.5 * length;
  const double quarter_turn = 0.5 * std::numbers::pi;

  // Ring profiles (distance from the axis, z) from top to bottom, poles excluded.
  std::vector<std::pair<double, double>> rings;
  for (int k = 1; k < bands; ++k) {
    const double polar = quarter_turn * k / bands;
    rings.emplace_back(radius * std::sin(polar), half_length + radius * std::cos(polar));
  }
  // A cylinder much shorter than the radius would only add sliver triangles:
  // its two equators become one ring at z = 0, still on the capsule.
  if (length > 1e-6 * radius) {
    rings.emplace_back(radius, half_length);
    rings.emplace_back(radius, -half_length);
  } else {
    rings.emplace_back(radius, 0.0);
  }
  for (int k = bands - 1; k >= 1; --k) {
    const double polar = quarter_turn * k / bands;
    rings.emplace_back(radius * std::sin(polar), -half_length - radius * std::cos(polar));
  }

  MeshBuilder builder;
  const int top = builder.add_vertex(Vec3(0, 0, half_length + radius));
  const int first_ring = top + 1;
  for (const auto& [rho, z] : rings) {
    for (int j = 0; j < segments; ++j) {
      const double azimuth = 2.0 * std::numbers::pi * j / segments;
      builder.add_vertex(Vec3(rho * std::cos(azimuth), rho * std::sin(azimuth), z));
    }
  }
  const int bottom = builder.add_vertex(Vec3(0, 0, -half_length - radius));
  auto ring_vertex = [&](std::size_t ring, int j) {
    return first_ring + static_cast<int>(ring) * segments + (j % segments);
  };

  // Counter-clockwise seen from outside: azimuth grows to the viewer's right
  // on the side, counter-clockwise seen from above at the top.
  for (int j = 0; j < segments; ++j)
    builder.add_triangle(top, ring_vertex(0, j), ring_vertex(0, j + 1));
  for (std::size_t r = 0; r + 1 < rings.size(); ++r) {
    for (int j = 0; j < segments; ++j) {
      const int upper = ring_vertex(r, j);
      const int upper_next = ring_vertex(r, j + 1);
      const int lower = ring_vertex(r + 1, j);
      const int lower_next = ring_vertex(r + 1, j + 1);
      builder.add_triangle(upper, lower, lower_next);
      builder.add_triangle(upper, lower_next, upper_next);
    }
  }
  const std::size_t last = rings.size() - 1;
  for (int j = 0; j < segments; ++j)
    builder.add_triangle(bottom, ring_vertex(last, j + 1), ring_vertex(last, j));
  return builder.take();
}

// An outer box with a rectangular hole through it along z: 16 vertices,
// 32 triangles, genus 1 (V - E + F = 16 - 48 + 32 = 0).
TriangleMesh box_with_hole_mesh(const Vec3& size, const Vec3& hole_size) {
  MeshBuilder builder;
  const Vec3 outer_half = 0.5 * size;
  const Vec3 inner_half(0.5 * hole_size.x(), 0.5 * hole_size.y(), outer_half.z());
  // Corners around each square counter-clockwise seen from +z, at z = -/+.
  const std::array<std::array<double, 2>, 4> square = {{{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}};
  std::array<std::array<int, 2>, 4> outer, inner;  // [corner][bottom, top]
  for (int c = 0; c < 4; ++c) {
    for (int level = 0; level < 2; ++level) {
      const double z = level ? outer_half.z() : -outer_half.z();
      outer[c][level] =
          builder.add_vertex(Vec3(square[c][0] * outer_half.x(), square[c][1] * outer_half.y(), z));
      inner[c][level] =
          builder.add_vertex(Vec3(square[c][0] * inner_half.x(), square[c][1] * inner_half.y(), z));
    }
  }
  for (int c = 0; c < 4; ++c) {
    const int n = (c + 1) % 4;
    // Side c runs from corner c to corner n; its outward direction in xy.
    const Vec3 side_midpoint(0.5 * (square[c][0] + square[n][0]),
                             0.5 * (square[c][1] + square[n][1]), 0.0);
    builder.add_quad(outer[c][0], outer[n][0], outer[n][1], outer[c][1], side_midpoint);
    // The hole's walls face into the hole, towards the axis.
    builder.add_quad(inner[c][0], inner[n][0], inner[n][1], inner[c][1], -side_midpoint);
    builder.add_quad(outer[c][1], outer[n][1], inner[n][1], inner[c][1], Vec3::UnitZ());
    builder.add_quad(outer[c][0], outer[n][0], inner[n][0], inner[c][0], -Vec3::UnitZ());
  }
  return builder.take();
}

// Closest point on the surface of the box [-half, half]. A component of
// `half` may be infinite (a prism unbounded along that axis).
SurfacePoint box_surface_point(const Vec3& half, const Vec3& p) {
  const Vec3 excess = p.cwiseAbs() - half;  // > 0 along axes where p is outside
  if ((excess.array() > 0.0).any()) {
    const Vec3 point = p.cwiseMax(-half).cwiseMin(half);
    const Vec3 offset = p - point;
    const double distance = offset.norm();
    return {point, offset / distance, distance};
  }
  // Inside or on the surface: the nearest face is the one with the least depth.
  int axis = 0;
  excess.maxCoeff(&axis);
  const double side = p[axis] >= 0.0 ? 1.0 : -1.0;
  Vec3 point = p;
  point[axis] = side * half[axis];
  return {point, side * Vec3::Unit(axis), excess[axis]};
}

SurfacePoint sphere_surface_point(double radius, const Vec3& p) {
  const double distance_from_centre = p.norm();
  // At the centre every direction is nearest; pick +z.
  const Vec3 normal = distance_from_centre > 0.0 ? Vec3(p / distance_from_centre) : Vec3::UnitZ();
  return {radius * normal, normal, distance_from_centre - radius};
}

SurfacePoint capsule_surface_point(double radius, double length, const Vec3& p) {
  const double half_length = 0.5 * length;
  const Vec3 axis_point(0, 0, std::clamp(p.z(), -half_length, half_length));
  SurfacePoint result = sphere_surface_point(radius, p - axis_point);
  // On the axis every radial direction is nearest; pick +x rather than the
  // sphere's +z, which would point along the axis inside the cylinder.
  if ((p - axis_point).squaredNorm() == 0.0) {
    result.normal = Vec3::UnitX();
    result.point = radius * Vec3::UnitX();
  }
  result.point += axis_point;
  return result;
}

// The solid is the outer box minus the hole prism (unbounded along z).
// Inside the solid the distance to the boundary is the smaller of the
// distances to the box's faces and to the hole's walls. Outside it, the
// solid is the union of four bars around the hole, so the distance is the
// smallest distance to a bar; max(box_sd, -hole_sd) would only bound it
// from below near the hole's rims.
SurfacePoint box_with_hole_surface_point(const Vec3& size, const Vec3& hole_size, const Vec3& p) {
  const Vec3 half = 0.5 * size;
  const Vec3 hole_half(0.5 * hole_size.x(), 0.5 * hole_size.y(),
                       std::numeric_limits<double>::infinity());
  const SurfacePoint box = box_surface_point(half, p);
  const SurfacePoint hole = box_surface_point(hole_half, p);
  if (box.signed_distance <= 0.0 && hole.signed_distance >= 0.0) {
    if (-box.signed_distance <= hole.signed_distance) return box;
    // The solid's outward normal on a hole wall points into the hole.
    return {hole.point, -hole.normal, -hole.signed_distance};
  }

  const double bar_x_half = 0.25 * (size.x() - hole_size.x());
  const double bar_y_half = 0.25 * (size.y() - hole_size.y());
  const double bar_x_centre = 0.25 * (size.x() + hole_size.x());
  const double bar_y_centre = 0.25 * (size.y() + hole_size.y());
  const std::array<std::pair<Vec3, Vec3>, 4> bars = {{
      {Vec3(-bar_x_centre, 0, 0), Vec3(bar_x_half, half.y(), half.z())},
      {Vec3(bar_x_centre, 0, 0), Vec3(bar_x_half, half.y(), half.z())},
      {Vec3(0, -bar_y_centre, 0), Vec3(half.x(), bar_y_half, half.z())},
      {Vec3(0, bar_y_centre, 0), Vec3(half.x(), bar_y_half, half.z())},
  }};
  SurfacePoint nearest{Vec3::Zero(), Vec3::Zero(), std::numeric_limits<double>::infinity()};
  for (const auto& [centre, bar_half] : bars) {
    SurfacePoint candidate = box_surface_point(bar_half, p - centre);
    if (candidate.signed_distance < nearest.signed_distance) {
      candidate.point += centre;
      nearest = candidate;
    }
  }
  return nearest;
}

}  // namespace

TriangleMesh shape_mesh(const Shape& shape) {
  require_valid_shape(shape);
  switch (shape.type) {
    case ShapeType::kBox:
      return box_mesh(shape.size);
    case ShapeType::kSphere:
      return sphere_mesh(shape.radius, shape.subdivisions);
    case ShapeType::kCapsule:
      return capsule_mesh(shape.radius, shape.length, shape.subdivisions);
    case ShapeType::kBoxWithHole:
      return box_with_hole_mesh(shape.size, shape.hole_size);
  }
  return {};
}

double shape_signed_distance(const Shape& shape, const Vec3& point) {
  switch (shape.type) {
    case ShapeType::kBox: {
      const Vec3 excess = point.cwiseAbs() - 0.5 * shape.size;
      return excess.cwiseMax(0.0).norm() + std::min(excess.maxCoeff(), 0.0);
    }
    case ShapeType::kSphere:
      return point.norm() - shape.radius;
    case ShapeType::kCapsule: {
      const double half_length = 0.5 * shape.length;
      const Vec3 axis_point(0, 0, std::clamp(point.z(), -half_length, half_length));
      return (point - axis_point).norm() - shape.radius;
    }
    case ShapeType::kBoxWithHole:
      return box_with_hole_surface_point(shape.size, shape.hole_size, point).signed_distance;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

SurfacePoint shape_closest_surface_point(const Shape& shape, const Vec3& point) {
  switch (shape.type) {
    case ShapeType::kBox:
      return box_surface_point(0.5 * shape.size, point);
    case ShapeType::kSphere:
      return sphere_surface_point(shape.radius, point);
    case ShapeType::kCapsule:
      return capsule_surface_point(shape.radius, shape.length, point);
    case ShapeType::kBoxWithHole:
      return box_with_hole_surface_point(shape.size, shape.hole_size, point);
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  return {Vec3::Constant(nan), Vec3::Constant(nan), nan};
}

}  // namespace hb
