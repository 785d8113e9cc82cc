// The sensation-preserving contact query: convex–convex penetration and
// distance (GJK/EPA) against closed forms for boxes, an octahedron and an
// icosahedron, and on random convex polytopes against CGAL's exact
// polytope distance and a brute-force separating-axis penetration depth;
// the hierarchy traversal on hand-built two-level hierarchies (refinement
// against the perceptibility threshold, the node that is refined, contacts
// equal to the leaf pairs CGAL finds intersecting); k-means clustering
// against hand-computed centroids. Units m.
#include "algorithms/sensation_preserving/hierarchy_contacts.h"

#include <dlfcn.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <new>
#include <numbers>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "algorithms/sensation_preserving/convex_proximity.h"
#include "hapticbench/input_error.h"
#include "harness/mesh_io/mesh_io.h"
#include "tests/support/cgal_convex.h"

namespace hb::test {
/// Allocations through operator new by this thread while counting (the
/// operator below): the contact query keeps its buffers between calls.
thread_local bool counting_allocations = false;
thread_local int64_t allocations_counted = 0;

/// The definition the operators below shadow (the C++ library's, or the
/// address sanitizer's when it is linked): every allocation and release
/// goes through it, so the two always match.
template <class Function>
Function shadowed(const char* mangled_name) {
  return reinterpret_cast<Function>(dlsym(RTLD_NEXT, mangled_name));
}
}  // namespace hb::test

void* operator new(std::size_t size) {
  static const auto next = hb::test::shadowed<void* (*)(std::size_t)>("_Znwm");
  if (hb::test::counting_allocations) ++hb::test::allocations_counted;
  return next(size);
}
void operator delete(void* p) noexcept {
  static const auto next = hb::test::shadowed<void (*)(void*)>("_ZdlPv");
  next(p);
}
void operator delete(void* p, std::size_t size) noexcept {
  static const auto next = hb::test::shadowed<void (*)(void*, std::size_t)>("_ZdlPvm");
  next(p, size);
}

namespace hb {
namespace {

/// Allocations (operator new) `call` makes on this thread.
template <class Call>
int64_t allocations_of(Call&& call) {
  test::allocations_counted = 0;
  test::counting_allocations = true;
  call();
  test::counting_allocations = false;
  return test::allocations_counted;
}

// ---------------------------------------------------------------------------
// Shapes and poses

/// Corners of the box [-h, h] about `centre`.
std::vector<Vec3> box(const Vec3& h, const Vec3& centre = Vec3::Zero()) {
  std::vector<Vec3> v;
  for (int i = 0; i < 8; ++i)
    v.push_back(centre +
                Vec3(i & 1 ? h.x() : -h.x(), i & 2 ? h.y() : -h.y(), i & 4 ? h.z() : -h.z()));
  return v;
}

/// Octahedron with vertices at distance r on the axes.
std::vector<Vec3> octahedron(double r) {
  return {Vec3(r, 0, 0),  Vec3(-r, 0, 0), Vec3(0, r, 0),
          Vec3(0, -r, 0), Vec3(0, 0, r),  Vec3(0, 0, -r)};
}

/// Icosahedron (0, ±c, ±cφ) and its cyclic permutations: its lowest
/// vertices are (0, ±c, -cφ), an edge parallel to y.
std::vector<Vec3> icosahedron(double c) {
  const double phi = std::numbers::phi;
  std::vector<Vec3> v;
  for (const double s1 : {-1.0, 1.0})
    for (const double s2 : {-1.0, 1.0}) {
      v.emplace_back(0, s1 * c, s2 * c * phi);
      v.emplace_back(s1 * c, s2 * c * phi, 0);
      v.emplace_back(s2 * c * phi, 0, s1 * c);
    }
  return v;
}

Pose make_pose(const Vec3& p, const Vec3& rotation_vector = Vec3::Zero()) {
  return Pose{p, quat_from_rotation_vector(rotation_vector)};
}

/// A rigid placement used to move whole closed-form configurations.
const Pose kPlacement = make_pose(Vec3(0.3, -0.2, 0.7), Vec3(0.4, -0.9, 0.25));

std::vector<Vec3> placed(const std::vector<Vec3>& body, const Pose& pose) {
  std::vector<Vec3> out;
  for (const Vec3& v : body) out.push_back(pose.transform_point(v));
  return out;
}

Quat random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> gauss;
  return Quat(gauss(rng), gauss(rng), gauss(rng), gauss(rng)).normalized();
}

/// 6 to 14 random points in an anisotropic box of half-size up to s.
std::vector<Vec3> random_cloud(std::mt19937& rng, double s) {
  std::uniform_int_distribution<int> count(6, 14);
  std::uniform_real_distribution<double> unit(-1, 1), stretch(0.3, 1);
  const Vec3 half(s * stretch(rng), s * stretch(rng), s * stretch(rng));
  std::vector<Vec3> v(static_cast<std::size_t>(count(rng)));
  for (Vec3& x : v) x = Vec3(unit(rng), unit(rng), unit(rng)).cwiseProduct(half);
  return v;
}

// ---------------------------------------------------------------------------
// Brute-force references

double support(const std::vector<Vec3>& v, const Vec3& u) {
  double best = -std::numeric_limits<double>::infinity();
  for (const Vec3& x : v) best = std::max(best, u.dot(x));
  return best;
}

/// Penetration depth of overlapping conv(b) into conv(a) by the separating
/// axis theorem: the least translation over the face normals of a and of b
/// (every triple of points, a superset) and the cross products of their
/// edges (every pair of points). Exact up to rounding for overlapping sets.
double sat_depth(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  double best = std::numeric_limits<double>::infinity();
  const auto consider = [&](const Vec3& axis) {
    const double length = axis.norm();
    if (!(length > 1e-12)) return;
    const Vec3 u = axis / length;
    best = std::min(best, support(a, u) + support(b, -u));
    best = std::min(best, support(a, -u) + support(b, u));
  };
  for (const auto* set : {&a, &b})
    for (std::size_t i = 0; i < set->size(); ++i)
      for (std::size_t j = i + 1; j < set->size(); ++j)
        for (std::size_t k = j + 1; k < set->size(); ++k)
          consider(((*set)[j] - (*set)[i]).cross((*set)[k] - (*set)[i]));
  for (std::size_t i = 0; i < a.size(); ++i)
    for (std::size_t j = i + 1; j < a.size(); ++j)
      for (std::size_t k = 0; k < b.size(); ++k)
        for (std::size_t l = k + 1; l < b.size(); ++l) consider((a[j] - a[i]).cross(b[l] - b[k]));
  return best;
}

double extent(const std::vector<Vec3>& v) {
  double e = 0;
  for (const Vec3& x : v) e = std::max(e, (x - v[0]).norm());
  return e;
}

/// The contact point lies midway between a's extreme plane along the normal
/// and b's along its opposite, and its feet on those planes lie on a and b.
void check_contact_point(const ConvexProximity& r, const std::vector<Vec3>& a_world,
                         const std::vector<Vec3>& b_world, double scale) {
  const Vec3& n = r.normal;
  const double a_max = support(a_world, n), b_min = -support(b_world, -n);
  CHECK(n.dot(r.point) == Approx(0.5 * (a_max + b_min)).margin(1e-9 * scale));
  const Vec3 foot_a = r.point + (a_max - n.dot(r.point)) * n;
  const Vec3 foot_b = r.point + (b_min - n.dot(r.point)) * n;
  const double tolerance = 1e-6 * scale;
  CHECK(test::cgal_hull_squared_distance({foot_a}, a_world) <= tolerance * tolerance);
  CHECK(test::cgal_hull_squared_distance({foot_b}, b_world) <= tolerance * tolerance);
}

// ---------------------------------------------------------------------------
// Hand-built hierarchies

ConvexNode leaf(std::vector<Vec3> vertices, int level = 0) {
  ConvexNode node;
  node.vertices = std::move(vertices);
  for (const Vec3& v : node.vertices) node.centre += v;
  node.centre /= static_cast<double>(node.vertices.size());
  for (const Vec3& v : node.vertices) node.radius = std::max(node.radius, (v - node.centre).norm());
  node.level = level;
  return node;
}

/// Appends a parent of nodes c0 and c1 whose piece is the hull of theirs
/// (given by the union of their vertices) and whose sphere holds theirs.
int add_parent(ConvexHierarchy& h, int c0, int c1, double deviation, int level) {
  std::vector<Vec3> vertices = h.nodes[static_cast<std::size_t>(c0)].vertices;
  const auto& more = h.nodes[static_cast<std::size_t>(c1)].vertices;
  vertices.insert(vertices.end(), more.begin(), more.end());
  ConvexNode node = leaf(std::move(vertices), level);
  for (const int c : {c0, c1}) {
    const ConvexNode& child = h.nodes[static_cast<std::size_t>(c)];
    node.radius = std::max(node.radius, (child.centre - node.centre).norm() + child.radius);
  }
  node.deviation_m = deviation;
  node.children = {c0, c1};
  h.nodes.push_back(std::move(node));
  return static_cast<int>(h.nodes.size()) - 1;
}

ConvexHierarchy one_node(std::vector<Vec3> vertices) {
  ConvexHierarchy h;
  h.nodes.push_back(leaf(std::move(vertices)));
  h.root = 0;
  h.pieces_per_level = {1};
  return h;
}

/// Two leaves (nodes 0 and 1) under a root (node 2).
ConvexHierarchy two_level(std::vector<Vec3> leaf0, std::vector<Vec3> leaf1, double deviation) {
  ConvexHierarchy h;
  h.nodes.push_back(leaf(std::move(leaf0)));
  h.nodes.push_back(leaf(std::move(leaf1)));
  h.root = add_parent(h, 0, 1, deviation, 1);
  h.pieces_per_level = {2, 1};
  return h;
}

// ---------------------------------------------------------------------------
// Convex–convex closed forms

TEST_CASE(
    "box resting in a box: depth and normal exact and the point at the centre of the face "
    "overlap") {
  const std::vector<Vec3> scene = box(Vec3(1, 1, 0.5));
  const std::vector<Vec3> tool = box(Vec3(0.3, 0.2, 0.25));
  struct Case {
    Vec3 centre;
    double turn_about_z;
    Vec3 expected_point;  // scene frame
  };
  // Tool bottom 0.05 below the scene's top face (z = 0.5); in the last
  // case the tool overhangs the edge x = 1 and only x in [0.6, 1] overlaps.
  const double depth = 0.05;
  const double z = 0.5 + 0.25 - depth;
  for (const Case& c : {Case{Vec3(0.4, -0.5, z), 0.0, Vec3(0.4, -0.5, 0.5 - depth / 2)},
                        Case{Vec3(-0.2, 0.3, z), 0.7, Vec3(-0.2, 0.3, 0.5 - depth / 2)},
                        Case{Vec3(0.9, 0.1, z), 0.0, Vec3(0.8, 0.1, 0.5 - depth / 2)}}) {
    const Pose tool_pose = kPlacement * make_pose(c.centre, Vec3(0, 0, c.turn_about_z));
    const ConvexProximity r =
        convex_proximity(PlacedConvex{scene, kPlacement}, PlacedConvex{tool, tool_pose});
    REQUIRE(r.in_contact);
    CHECK(r.signed_depth == Approx(depth).margin(1e-12));
    CHECK((r.normal - kPlacement.q * Vec3::UnitZ()).norm() < 1e-12);
    CHECK((r.point - kPlacement.transform_point(c.expected_point)).norm() < 1e-12);
  }
}

TEST_CASE("octahedron vertex and icosahedron edge pressed into a box face") {
  const std::vector<Vec3> scene = box(Vec3(1, 1, 0.5));
  const double depth = 0.03;
  {
    // Vertex (0, 0, -0.2) reaches 0.03 below the top face.
    const Vec3 centre(0.3, 0.4, 0.5 + 0.2 - depth);
    const ConvexProximity r =
        convex_proximity(PlacedConvex{scene, kPlacement},
                         PlacedConvex{octahedron(0.2), kPlacement * make_pose(centre)});
    REQUIRE(r.in_contact);
    CHECK(r.signed_depth == Approx(depth).margin(1e-12));
    CHECK((r.normal - kPlacement.q * Vec3::UnitZ()).norm() < 1e-12);
    CHECK((r.point - kPlacement.transform_point(Vec3(0.3, 0.4, 0.5 - depth / 2))).norm() < 1e-12);
  }
  {
    // The lowest edge (0, ±c, -cφ): its midpoint is below the centre.
    const double c = 0.1;
    const Vec3 centre(-0.5, 0.2, 0.5 + c * std::numbers::phi - depth);
    const ConvexProximity r =
        convex_proximity(PlacedConvex{scene, kPlacement},
                         PlacedConvex{icosahedron(c), kPlacement * make_pose(centre)});
    REQUIRE(r.in_contact);
    CHECK(r.signed_depth == Approx(depth).margin(1e-12));
    CHECK((r.normal - kPlacement.q * Vec3::UnitZ()).norm() < 1e-12);
    CHECK((r.point - kPlacement.transform_point(Vec3(-0.5, 0.2, 0.5 - depth / 2))).norm() < 1e-12);
  }
}

TEST_CASE("crossed edges of two turned cubes: contact at the crossing") {
  // Scene cube turned 45° about y: top edge along y at z = h√2. Tool cube
  // turned 45° about x: bottom edge along x at z_t - h√2. Their overlap
  // along z is the least translation that separates them.
  const double h = 0.5, depth = 0.02;
  const double top = h * std::numbers::sqrt2;
  const double z_t = 2 * top - depth;
  const std::vector<Vec3> cube = box(Vec3(h, h, h));
  const Pose scene_pose = kPlacement * make_pose(Vec3::Zero(), Vec3(0, std::numbers::pi / 4, 0));
  const Pose tool_pose = kPlacement * make_pose(Vec3(0, 0, z_t), Vec3(std::numbers::pi / 4, 0, 0));
  const ConvexProximity r =
      convex_proximity(PlacedConvex{cube, scene_pose}, PlacedConvex{cube, tool_pose});
  REQUIRE(r.in_contact);
  CHECK(r.signed_depth == Approx(depth).margin(1e-12));
  CHECK((r.normal - kPlacement.q * Vec3::UnitZ()).norm() < 1e-12);
  CHECK((r.point - kPlacement.transform_point(Vec3(0, 0, top - depth / 2))).norm() < 1e-12);
}

TEST_CASE("separated boxes: exact distance and margin contacts and none without a margin") {
  const std::vector<Vec3> scene = box(Vec3(1, 1, 0.5));
  const std::vector<Vec3> tool = box(Vec3(0.3, 0.2, 0.25));
  SECTION("face over face, gap 0.01") {
    const double gap = 0.01;
    const Pose tool_pose = kPlacement * make_pose(Vec3(0.2, 0.1, 0.5 + 0.25 + gap));
    const PlacedConvex a{scene, kPlacement}, b{tool, tool_pose};
    CHECK(convex_distance(a, b) == Approx(gap).margin(1e-12));
    CHECK_FALSE(convex_proximity(a, b).in_contact);
    CHECK_FALSE(convex_proximity(a, b, 0.009).in_contact);
    const ConvexProximity r = convex_proximity(a, b, 0.02);
    REQUIRE(r.in_contact);
    CHECK(r.signed_depth == Approx(-gap).margin(1e-12));
    CHECK((r.normal - kPlacement.q * Vec3::UnitZ()).norm() < 1e-9);
    CHECK((r.point - kPlacement.transform_point(Vec3(0.2, 0.1, 0.5 + gap / 2))).norm() < 1e-9);
  }
  SECTION("corner to corner") {
    const Vec3 offset(0.01, 0.02, 0.03);
    const Vec3 corner_a(1, 1, 0.5), corner_b = corner_a + offset;
    const Pose tool_pose = kPlacement * make_pose(corner_b + Vec3(0.3, 0.2, 0.25));
    const PlacedConvex a{scene, kPlacement}, b{tool, tool_pose};
    CHECK(convex_distance(a, b) == Approx(offset.norm()).margin(1e-12));
    const ConvexProximity r = convex_proximity(a, b, 0.05);
    REQUIRE(r.in_contact);
    CHECK(r.signed_depth == Approx(-offset.norm()).margin(1e-12));
    CHECK((r.normal - kPlacement.q * offset.normalized()).norm() < 1e-9);
    CHECK((r.point - kPlacement.transform_point(0.5 * (corner_a + corner_b))).norm() < 1e-9);
  }
}

TEST_CASE("convex proximity rejects an empty piece and a bad margin") {
  const std::vector<Vec3> cube = box(Vec3(1, 1, 1));
  const std::vector<Vec3> none;
  CHECK_THROWS_AS(convex_proximity(PlacedConvex{none, Pose{}}, PlacedConvex{cube, Pose{}}),
                  InputError);
  CHECK_THROWS_AS(convex_proximity(PlacedConvex{cube, Pose{}}, PlacedConvex{cube, Pose{}}, -1),
                  InputError);
}

// ---------------------------------------------------------------------------
// Random convex polytopes against CGAL and the separating-axis depth

TEST_CASE("random convex polytopes: overlap and depth and distance against exact references") {
  std::mt19937 rng(20240611);
  std::uniform_real_distribution<double> offset(-0.05, 0.05);
  const double s = 0.05;
  int overlapping = 0, separated = 0, ambiguous = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const std::vector<Vec3> a_body = random_cloud(rng, s), b_body = random_cloud(rng, s);
    const Pose a_pose{Vec3(offset(rng), offset(rng), offset(rng)), random_rotation(rng)};
    const Pose b_pose{a_pose.p + Vec3(offset(rng), offset(rng), offset(rng)), random_rotation(rng)};
    const std::vector<Vec3> a_world = placed(a_body, a_pose), b_world = placed(b_body, b_pose);
    const PlacedConvex a{a_body, a_pose}, b{b_body, b_pose};
    const double scale = std::max(extent(a_world), extent(b_world));
    const double exact_squared = test::cgal_hull_squared_distance(a_world, b_world);
    INFO("trial " << trial);
    if (test::cgal_hulls_intersect(a_world, b_world)) {
      const double depth = sat_depth(a_world, b_world);
      if (depth < 1e-9 * scale) {
        ++ambiguous;
        continue;
      }
      ++overlapping;
      CHECK(convex_distance(a, b) == 0);
      const ConvexProximity r = convex_proximity(a, b);
      REQUIRE(r.in_contact);
      CHECK(std::abs(r.normal.norm() - 1) < 1e-12);
      // signed_depth is the translation along the normal that separates
      // them; it is least (the penetration depth) only for the best normal.
      CHECK(r.signed_depth ==
            Approx(support(a_world, r.normal) + support(b_world, -r.normal)).margin(1e-12 * scale));
      CHECK(r.signed_depth == Approx(depth).margin(1e-9 * scale));
      check_contact_point(r, a_world, b_world, scale);
      // With a margin the overlapping pair gives the same answer.
      const ConvexProximity with_margin = convex_proximity(a, b, 0.01);
      REQUIRE(with_margin.in_contact);
      CHECK(with_margin.signed_depth == Approx(depth).margin(1e-9 * scale));
    } else {
      const double distance = std::sqrt(exact_squared);
      if (distance < 1e-9 * scale) {
        ++ambiguous;
        continue;
      }
      ++separated;
      CHECK_FALSE(convex_proximity(a, b).in_contact);
      CHECK(convex_distance(a, b) == Approx(distance).margin(1e-9 * scale));
      CHECK_FALSE(convex_proximity(a, b, 0.999 * distance).in_contact);
      const ConvexProximity r = convex_proximity(a, b, 1.001 * distance + 1e-6);
      REQUIRE(r.in_contact);
      CHECK(r.signed_depth == Approx(-distance).margin(1e-9 * scale));
      check_contact_point(r, a_world, b_world, scale);
    }
  }
  INFO("overlapping " << overlapping << ", separated " << separated << ", ambiguous " << ambiguous);
  CHECK(overlapping > 80);
  CHECK(separated > 80);
  CHECK(ambiguous < 5);
}

TEST_CASE("thin overlapping pieces: the depth is the least separating translation") {
  // Pieces of a surface decomposition are thin and nearly flat, where EPA
  // stops on wrong faces and the polishing of its normal decides the
  // depth: plates 1/200 as thick as they are wide, of 20 to 40 vertices,
  // crossing at random angles, against the separating-axis reference.
  std::mt19937 rng(5150);
  std::uniform_real_distribution<double> unit(-1, 1), offset(-0.01, 0.01);
  std::uniform_int_distribution<int> count(20, 40);
  const double s = 0.05;
  const auto plate = [&] {
    std::vector<Vec3> v(static_cast<std::size_t>(count(rng)));
    for (Vec3& x : v) x = Vec3(s * unit(rng), s * unit(rng), 0.005 * s * unit(rng));
    return v;
  };
  int overlapping = 0;
  for (int trial = 0; trial < 100; ++trial) {
    const std::vector<Vec3> a_body = plate(), b_body = plate();
    const Pose a_pose{Vec3::Zero(), random_rotation(rng)};
    const Pose b_pose{Vec3(offset(rng), offset(rng), offset(rng)), random_rotation(rng)};
    const std::vector<Vec3> a_world = placed(a_body, a_pose), b_world = placed(b_body, b_pose);
    if (!test::cgal_hulls_intersect(a_world, b_world)) continue;
    const double scale = std::max(extent(a_world), extent(b_world));
    const double depth = sat_depth(a_world, b_world);
    if (depth < 1e-9 * scale) continue;
    ++overlapping;
    INFO("trial " << trial);
    const ConvexProximity r =
        convex_proximity(PlacedConvex{a_body, a_pose}, PlacedConvex{b_body, b_pose});
    REQUIRE(r.in_contact);
    CHECK(r.signed_depth == Approx(depth).margin(1e-9 * scale));
  }
  CHECK(overlapping > 40);
}

// ---------------------------------------------------------------------------
// Hierarchy traversal

// Scene: two unit cubes 1 apart along x (nodes 0, 1) under a root (node 2)
// whose piece, their hull, bridges the gap x in (-0.5, 0.5) that is 1 deep.
ConvexHierarchy bridged_cubes() {
  return two_level(box(Vec3(0.5, 0.5, 0.5), Vec3(-1, 0, 0)),
                   box(Vec3(0.5, 0.5, 0.5), Vec3(1, 0, 0)), 1.0);
}

const Pose kScenePose = make_pose(Vec3(0.1, 0.2, -0.3), Vec3(0.2, 0.1, -0.4));

TEST_CASE("perceptibility: threshold 0 reaches the leaves and a large one stops at the root pair") {
  const ConvexHierarchy scene = bridged_cubes();
  // Tool: a slab over the gap, 0.03 into the root's piece, 0.05 from each
  // cube; its sphere meets both cubes' spheres.
  const ConvexHierarchy tool = one_node(box(Vec3(0.45, 0.1, 0.1)));
  const double depth = 0.03;
  const Pose tool_pose = kScenePose * make_pose(Vec3(0, 0, 0.5 + 0.1 - depth));
  const double ratio = scene.nodes[2].deviation_m / tool.nodes[0].radius;
  REQUIRE(tool.nodes[0].radius < scene.nodes[2].radius);

  SECTION("full resolution") {
    for (const double threshold : {0.0, 0.99 * ratio}) {
      std::vector<PieceContact> contacts;
      HierarchyContactStats stats;
      find_hierarchy_contacts(tool, tool_pose, scene, kScenePose, {threshold, 0}, contacts, stats);
      CHECK(contacts.empty());
      CHECK(stats.node_pairs_tested == 3);
      CHECK(stats.gjk_calls == 2);
      CHECK(stats.deepest_level_reached == 0);
    }
  }
  SECTION("root pair only") {
    for (const double threshold : {1.01 * ratio, 1e6}) {
      std::vector<PieceContact> contacts;
      HierarchyContactStats stats;
      find_hierarchy_contacts(tool, tool_pose, scene, kScenePose, {threshold, 0}, contacts, stats);
      CHECK(stats.node_pairs_tested == 1);
      CHECK(stats.gjk_calls == 1);
      CHECK(stats.deepest_level_reached == 0);  // the tool's only node is a leaf
      REQUIRE(contacts.size() == 1);
      CHECK(contacts[0].scene_node == 2);
      CHECK(contacts[0].tool_node == 0);
      CHECK(contacts[0].depth == Approx(depth).margin(1e-12));
      CHECK(contacts[0].gap_m == 0);
      CHECK((contacts[0].normal - kScenePose.q * Vec3::UnitZ()).norm() < 1e-12);
      CHECK((contacts[0].point - kScenePose.transform_point(Vec3(0, 0, 0.5 - depth / 2))).norm() <
            1e-12);
    }
  }
  SECTION("a margin finds the two cubes 0.05 away") {
    std::vector<PieceContact> contacts;
    HierarchyContactStats stats;
    find_hierarchy_contacts(tool, tool_pose, scene, kScenePose, {0, 0.06}, contacts, stats);
    REQUIRE(contacts.size() == 2);
    for (const int i : {0, 1}) {
      const PieceContact& c = contacts[static_cast<std::size_t>(i)];
      CHECK(c.scene_node == i);
      CHECK(c.depth == 0);
      CHECK(c.gap_m == Approx(0.05).margin(1e-9));
      const Vec3 away = kScenePose.q * Vec3(i == 0 ? 1 : -1, 0, 0);
      CHECK((c.normal - away).norm() < 1e-9);
    }
  }
}

TEST_CASE("threshold 0 finds the leaf a tool presses and culls the other by its sphere") {
  const ConvexHierarchy scene = bridged_cubes();
  const ConvexHierarchy tool = one_node(box(Vec3(0.2, 0.1, 0.1)));
  const double depth = 0.03;
  const Pose tool_pose = kScenePose * make_pose(Vec3(1.1, -0.2, 0.5 + 0.1 - depth));
  std::vector<PieceContact> contacts;
  HierarchyContactStats stats;
  find_hierarchy_contacts(tool, tool_pose, scene, kScenePose, {0, 0}, contacts, stats);
  CHECK(stats.node_pairs_tested == 3);
  CHECK(stats.gjk_calls == 1);
  REQUIRE(contacts.size() == 1);
  CHECK(contacts[0].scene_node == 1);
  CHECK(contacts[0].depth == Approx(depth).margin(1e-12));
  CHECK((contacts[0].point - kScenePose.transform_point(Vec3(1.1, -0.2, 0.5 - depth / 2))).norm() <
        1e-12);
}

TEST_CASE("the node with the larger sphere is refined: a two-piece tool on a small block") {
  // Tool: two cubes at x = ±1 (nodes 0, 1) under a root; scene: a block
  // under cube 1 that it presses 0.02 deep.
  const ConvexHierarchy tool = two_level(box(Vec3(0.2, 0.2, 0.2), Vec3(-1, 0, 0)),
                                         box(Vec3(0.2, 0.2, 0.2), Vec3(1, 0, 0)), 0.3);
  const ConvexHierarchy scene = one_node(box(Vec3(0.3, 0.3, 0.1)));
  REQUIRE(tool.nodes[2].radius > scene.nodes[0].radius);
  const Pose tool_pose = kScenePose * make_pose(Vec3(-1, 0, 0.1 + 0.2 - 0.02));
  std::vector<PieceContact> contacts;
  HierarchyContactStats stats;
  find_hierarchy_contacts(tool, tool_pose, scene, kScenePose, {0, 0}, contacts, stats);
  CHECK(stats.node_pairs_tested == 3);
  REQUIRE(contacts.size() == 1);
  CHECK(contacts[0].tool_node == 1);
  CHECK(contacts[0].scene_node == 0);
  CHECK(contacts[0].depth == Approx(0.02).margin(1e-12));
  CHECK((contacts[0].normal - kScenePose.q * Vec3::UnitZ()).norm() < 1e-12);
  // Counters add up over calls.
  find_hierarchy_contacts(tool, tool_pose, scene, kScenePose, {0, 0}, contacts, stats);
  CHECK(stats.node_pairs_tested == 6);
  CHECK(contacts.size() == 2);
}

/// Four random pieces (nodes 0-3) paired under nodes 4, 5 and a root 6.
ConvexHierarchy random_hierarchy(std::mt19937& rng) {
  std::uniform_real_distribution<double> spread(-0.08, 0.08);
  ConvexHierarchy h;
  for (int i = 0; i < 4; ++i) {
    std::vector<Vec3> cloud = random_cloud(rng, 0.04);
    const Vec3 shift(spread(rng), spread(rng), spread(rng));
    for (Vec3& v : cloud) v += shift;
    h.nodes.push_back(leaf(std::move(cloud)));
  }
  const int left = add_parent(h, 0, 1, 0.01, 1), right = add_parent(h, 2, 3, 0.01, 1);
  h.root = add_parent(h, left, right, 0.02, 2);
  h.pieces_per_level = {4, 2, 1};
  return h;
}

TEST_CASE("threshold 0: the contacts are exactly the leaf pairs CGAL finds intersecting") {
  std::mt19937 rng(77);
  std::uniform_real_distribution<double> offset(-0.06, 0.06);
  int pairs_found = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const ConvexHierarchy tool = random_hierarchy(rng), scene = random_hierarchy(rng);
    const Pose scene_pose{Vec3(offset(rng), offset(rng), offset(rng)), random_rotation(rng)};
    const Pose tool_pose{scene_pose.p + Vec3(offset(rng), offset(rng), offset(rng)),
                         random_rotation(rng)};
    std::vector<PieceContact> contacts;
    HierarchyContactStats stats;
    find_hierarchy_contacts(tool, tool_pose, scene, scene_pose, {0, 0}, contacts, stats);
    std::set<std::pair<int, int>> found, expected;
    bool ambiguous = false;
    for (const PieceContact& c : contacts) {
      CHECK(tool.nodes[static_cast<std::size_t>(c.tool_node)].children[0] == -1);
      CHECK(scene.nodes[static_cast<std::size_t>(c.scene_node)].children[0] == -1);
      found.emplace(c.tool_node, c.scene_node);
    }
    for (int t = 0; t < 4; ++t)
      for (int s = 0; s < 4; ++s) {
        const std::vector<Vec3> tw =
            placed(tool.nodes[static_cast<std::size_t>(t)].vertices, tool_pose);
        const std::vector<Vec3> sw =
            placed(scene.nodes[static_cast<std::size_t>(s)].vertices, scene_pose);
        if (test::cgal_hulls_intersect(tw, sw)) {
          expected.emplace(t, s);
          ambiguous = ambiguous || sat_depth(sw, tw) < 1e-9;
        } else {
          ambiguous = ambiguous || test::cgal_hull_squared_distance(tw, sw) < 1e-18;
        }
      }
    if (ambiguous) continue;
    INFO("trial " << trial);
    CHECK(found == expected);
    CHECK(stats.deepest_level_reached == 0);
    pairs_found += static_cast<int>(expected.size());
  }
  CHECK(pairs_found > 20);
}

Eigen::AlignedBox3d bounding_box(const std::vector<Vec3>& points) {
  Eigen::AlignedBox3d box;
  for (const Vec3& x : points) box.extend(x);
  return box;
}

TEST_CASE(
    "built hierarchies of two knots: leaf contacts match CGAL and coarse answers obey the rule") {
  const std::string path =
      (std::filesystem::path(HAPTICBENCH_SOURCE_DIR) / "models/knot1.off").string();
  if (!std::filesystem::exists(path))
    FAIL(path << " is missing: run scripts/extract-models (CMake's configure step runs it)");
  const TriangleMesh mesh = read_mesh_file(path, 0.05);
  const ConvexHierarchy knot = build_convex_hierarchy(mesh, ConvexHierarchySettings{});
  REQUIRE(knot.pieces_per_level.size() >= 3);
  const auto is_leaf = [&](int n) {
    return knot.nodes[static_cast<std::size_t>(n)].children[0] < 0;
  };
  const double size = 2 * knot.nodes[static_cast<std::size_t>(knot.root)].radius;
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> shift(-0.15 * size, 0.15 * size);
  int leaf_pairs_found = 0;
  for (int trial = 0; trial < 2; ++trial) {
    INFO("trial " << trial);
    const Pose scene_pose{Vec3(0.1, 0, 0), random_rotation(rng)};
    const Pose tool_pose{scene_pose.p + Vec3(shift(rng), shift(rng), shift(rng)),
                         random_rotation(rng)};

    // Full resolution: exactly the intersecting leaf pairs.
    std::vector<PieceContact> contacts;
    HierarchyContactStats stats;
    find_hierarchy_contacts(knot, tool_pose, knot, scene_pose, {0, 0}, contacts, stats);
    std::set<std::pair<int, int>> found, expected;
    for (const PieceContact& c : contacts) {
      CHECK(is_leaf(c.tool_node));
      CHECK(is_leaf(c.scene_node));
      found.emplace(c.tool_node, c.scene_node);
    }
    std::vector<int> leaves;
    for (int n = 0; n < static_cast<int>(knot.nodes.size()); ++n)
      if (is_leaf(n)) leaves.push_back(n);
    std::vector<std::vector<Vec3>> tool_leaves, scene_leaves;
    std::vector<Eigen::AlignedBox3d> tool_boxes, scene_boxes;
    for (const int n : leaves) {
      tool_leaves.push_back(placed(knot.nodes[static_cast<std::size_t>(n)].vertices, tool_pose));
      scene_leaves.push_back(placed(knot.nodes[static_cast<std::size_t>(n)].vertices, scene_pose));
      tool_boxes.push_back(bounding_box(tool_leaves.back()));
      scene_boxes.push_back(bounding_box(scene_leaves.back()));
    }
    // Random poses: no pair touches within rounding (fixed seed).
    for (std::size_t t = 0; t < leaves.size(); ++t)
      for (std::size_t s = 0; s < leaves.size(); ++s)
        if (tool_boxes[t].intersects(scene_boxes[s]) &&
            test::cgal_hulls_intersect(tool_leaves[t], scene_leaves[s]))
          expected.emplace(leaves[t], leaves[s]);
    std::vector<std::pair<int, int>> missed, extra;
    std::set_difference(expected.begin(), expected.end(), found.begin(), found.end(),
                        std::back_inserter(missed));
    std::set_difference(found.begin(), found.end(), expected.begin(), expected.end(),
                        std::back_inserter(extra));
    for (const auto& [t, s] : missed) {
      const std::vector<Vec3> tw =
          placed(knot.nodes[static_cast<std::size_t>(t)].vertices, tool_pose);
      const std::vector<Vec3> sw =
          placed(knot.nodes[static_cast<std::size_t>(s)].vertices, scene_pose);
      const ConvexProximity r =
          convex_proximity(PlacedConvex{sw, Pose{}}, PlacedConvex{tw, Pose{}});
      WARN("missed " << t << " " << s << " nv " << tw.size() << " " << sw.size() << " in "
                     << r.in_contact << " depth " << r.signed_depth << " sat "
                     << (tw.size() < 40 && sw.size() < 40 ? sat_depth(sw, tw) : -1.0));
    }
    for (const auto& [t, s] : extra) {
      const std::vector<Vec3> tw =
          placed(knot.nodes[static_cast<std::size_t>(t)].vertices, tool_pose);
      const std::vector<Vec3> sw =
          placed(knot.nodes[static_cast<std::size_t>(s)].vertices, scene_pose);
      WARN("extra " << t << " " << s << " cgal d2 " << test::cgal_hull_squared_distance(tw, sw));
    }
    CHECK(missed.empty());
    CHECK(extra.empty());
    CHECK(stats.deepest_level_reached == 0);
    leaf_pairs_found += static_cast<int>(expected.size());

    // The root pair alone when nothing is perceptible.
    std::vector<PieceContact> coarse;
    HierarchyContactStats coarse_stats;
    find_hierarchy_contacts(knot, tool_pose, knot, scene_pose, {1e9, 0}, coarse, coarse_stats);
    CHECK(coarse_stats.node_pairs_tested == 1);
    CHECK(coarse_stats.gjk_calls == 1);
    CHECK(coarse_stats.deepest_level_reached ==
          knot.nodes[static_cast<std::size_t>(knot.root)].level);
    CHECK(coarse.size() == 1);

    // In between, a pair is answered at a coarse level only where the
    // finer detail is imperceptible, and with fewer queries.
    std::vector<PieceContact> mid;
    HierarchyContactStats mid_stats;
    const double threshold = 0.05;
    find_hierarchy_contacts(knot, tool_pose, knot, scene_pose, {threshold, 0}, mid, mid_stats);
    CHECK(mid_stats.gjk_calls <= stats.gjk_calls);
    for (const PieceContact& c : mid) {
      const ConvexNode& t = knot.nodes[static_cast<std::size_t>(c.tool_node)];
      const ConvexNode& s = knot.nodes[static_cast<std::size_t>(c.scene_node)];
      if (is_leaf(c.tool_node) && is_leaf(c.scene_node)) continue;
      CHECK(std::max(t.deviation_m, s.deviation_m) <= threshold * std::min(t.radius, s.radius));
    }
  }
  CHECK(leaf_pairs_found > 10);
}

TEST_CASE("hierarchy query input checks") {
  const ConvexHierarchy cube = one_node(box(Vec3(1, 1, 1)));
  std::vector<PieceContact> contacts;
  HierarchyContactStats stats;
  CHECK_THROWS_AS(find_hierarchy_contacts(cube, Pose{}, cube, Pose{}, {-0.1, 0}, contacts, stats),
                  InputError);
  CHECK_THROWS_AS(find_hierarchy_contacts(cube, Pose{}, cube, Pose{}, {0.1, -1}, contacts, stats),
                  InputError);
  ConvexHierarchy broken = cube;
  broken.root = 3;
  CHECK_THROWS_AS(find_hierarchy_contacts(cube, Pose{}, broken, Pose{}, {0.1, 0}, contacts, stats),
                  InputError);
  const ConvexHierarchy empty;
  find_hierarchy_contacts(cube, Pose{}, empty, Pose{}, {0.1, 0}, contacts, stats);
  CHECK(contacts.empty());
  CHECK(stats.node_pairs_tested == 0);
}

// ---------------------------------------------------------------------------
// Clustering

PieceContact contact(const Vec3& point, const Vec3& normal, double depth) {
  PieceContact c;
  c.point = point;
  c.normal = normal;
  c.depth = depth;
  return c;
}

bool same(const std::vector<ContactCluster>& a, const std::vector<ContactCluster>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i].point != b[i].point || a[i].normal != b[i].normal || a[i].depth != b[i].depth ||
        a[i].members != b[i].members)
      return false;
  return true;
}

std::vector<PieceContact> two_groups(std::mt19937& rng, const Vec3& c0, const Vec3& c1) {
  std::uniform_real_distribution<double> jitter(-0.01, 0.01), depth(0.001, 0.01);
  std::vector<PieceContact> contacts;
  for (int i = 0; i < 40; ++i) {
    const Vec3 centre = i % 2 ? c1 : c0;
    const Vec3 normal = Vec3(jitter(rng), jitter(rng), 1).normalized();
    contacts.push_back(
        contact(centre + Vec3(jitter(rng), jitter(rng), jitter(rng)), normal, depth(rng)));
  }
  return contacts;
}

TEST_CASE("k-means: two separated groups give their means and depth-weighted unit normals") {
  std::mt19937 rng(5);
  const Vec3 c0(0, 0, 0), c1(0.5, 0.1, 0);
  const std::vector<PieceContact> contacts = two_groups(rng, c0, c1);
  const std::vector<ContactCluster> clusters = cluster_contacts(contacts, 2);
  REQUIRE(clusters.size() == 2);
  for (const ContactCluster& cluster : clusters) {
    const int group = (cluster.point - c0).norm() < (cluster.point - c1).norm() ? 0 : 1;
    Vec3 mean = Vec3::Zero(), weighted = Vec3::Zero();
    double deepest = 0;
    for (std::size_t i = static_cast<std::size_t>(group); i < contacts.size(); i += 2) {
      mean += contacts[i].point / 20;
      weighted += contacts[i].depth * contacts[i].normal;
      deepest = std::max(deepest, contacts[i].depth);
    }
    CHECK(cluster.members == 20);
    CHECK((cluster.point - mean).norm() < 1e-12);
    CHECK((cluster.normal - weighted.normalized()).norm() < 1e-12);
    CHECK(cluster.normal.norm() == Approx(1).margin(1e-14));
    CHECK(cluster.depth == deepest);
  }
  // The deepest contact's cluster comes first.
  const auto deepest = std::max_element(
      contacts.begin(), contacts.end(),
      [](const PieceContact& a, const PieceContact& b) { return a.depth < b.depth; });
  CHECK(clusters[0].depth == deepest->depth);
}

TEST_CASE("k-means: deterministic and independent of the order of the contacts") {
  std::mt19937 rng(9);
  std::vector<PieceContact> contacts = two_groups(rng, Vec3(0, 0, 0), Vec3(0.05, 0.02, 0));
  for (int i = 0; i < 20; ++i) {
    std::uniform_real_distribution<double> u(-0.1, 0.1);
    contacts.push_back(contact(Vec3(u(rng), u(rng), u(rng)), Vec3::UnitX(), 0.002));
  }
  for (const int k : {1, 3, 5}) {
    const std::vector<ContactCluster> first = cluster_contacts(contacts, k);
    CHECK(same(first, cluster_contacts(contacts, k)));
    std::vector<PieceContact> shuffled = contacts;
    std::shuffle(shuffled.begin(), shuffled.end(), rng);
    CHECK(same(first, cluster_contacts(shuffled, k)));
    int members = 0;
    for (const ContactCluster& c : first) members += c.members;
    CHECK(members == static_cast<int>(contacts.size()));
    CHECK(static_cast<int>(first.size()) <= k);
  }
}

TEST_CASE("k-means: k at least the number of contacts keeps each contact") {
  const std::vector<PieceContact> contacts = {
      contact(Vec3(0, 0, 0), Vec3(0, 0, 2), 0.01),  // normal not unit: made unit
      contact(Vec3(0, 0, 0), Vec3(1, 0, 0), 0.03),  // same point, deeper
      contact(Vec3(1, 2, 3), Vec3(0, 1, 0), 0.02)};
  for (const int k : {3, 10}) {
    const std::vector<ContactCluster> clusters = cluster_contacts(contacts, k);
    REQUIRE(clusters.size() == 3);
    // Deepest first.
    CHECK(clusters[0].depth == 0.03);
    CHECK(clusters[0].normal == Vec3(1, 0, 0));
    CHECK(clusters[1].depth == 0.02);
    CHECK(clusters[1].point == Vec3(1, 2, 3));
    CHECK(clusters[2].depth == 0.01);
    CHECK(clusters[2].normal == Vec3(0, 0, 1));
    for (const ContactCluster& c : clusters) CHECK(c.members == 1);
  }
}

TEST_CASE(
    "k-means: one cluster holds the mean point and the depth-weighted normal and the deepest "
    "depth") {
  const std::vector<PieceContact> contacts = {contact(Vec3(0, 0, 0), Vec3(1, 0, 0), 3),
                                              contact(Vec3(2, 0, 0), Vec3(0, 1, 0), 1),
                                              contact(Vec3(1, 3, 0), Vec3(0, 1, 0), 0)};
  const std::vector<ContactCluster> clusters = cluster_contacts(contacts, 1);
  REQUIRE(clusters.size() == 1);
  CHECK((clusters[0].point - Vec3(1, 1, 0)).norm() < 1e-15);
  CHECK((clusters[0].normal - Vec3(3, 1, 0) / std::sqrt(10.0)).norm() < 1e-15);
  CHECK(clusters[0].depth == 3);
  CHECK(clusters[0].members == 3);
  // Margin contacts (depth 0 throughout): the plain mean of the normals.
  const std::vector<ContactCluster> touching = cluster_contacts(
      {contact(Vec3(0, 0, 0), Vec3(1, 0, 0), 0), contact(Vec3(0, 1, 0), Vec3(0, 1, 0), 0)}, 1);
  REQUIRE(touching.size() == 1);
  CHECK((touching[0].normal - Vec3(1, 1, 0).normalized()).norm() < 1e-15);
  CHECK(cluster_contacts({}, 4).empty());
  CHECK_THROWS_AS(cluster_contacts(contacts, 0), InputError);
}

TEST_CASE("k-means: a cluster's depth is signed, pairs within the margin count minus their gap") {
  // Pairs apart by 0.4 and 0.7 mm (within the contact margin): the cluster
  // acts only once the nearer gap closes, as the unclustered contacts do.
  PieceContact near = contact(Vec3(0, 0, 0), Vec3(0, 0, 1), 0);
  near.gap_m = 0.0004;
  PieceContact nearer = contact(Vec3(0.01, 0, 0), Vec3(0, 0, 1), 0);
  nearer.gap_m = 0.0007;
  const std::vector<ContactCluster> apart = cluster_contacts({near, nearer}, 1);
  REQUIRE(apart.size() == 1);
  CHECK(apart[0].depth == -0.0004);
  // One member penetrating 0.2 mm: the cluster's depth is its depth.
  const std::vector<ContactCluster> touching =
      cluster_contacts({near, contact(Vec3(0.02, 0, 0), Vec3(0, 0, 1), 0.0002)}, 1);
  REQUIRE(touching.size() == 1);
  CHECK(touching[0].depth == 0.0002);
  // One cluster per contact keeps each signed depth.
  const std::vector<ContactCluster> each = cluster_contacts({near, nearer}, 2);
  REQUIRE(each.size() == 2);
  CHECK(std::min(each[0].depth, each[1].depth) == -0.0007);
}

TEST_CASE("directions kept from the last query give the same contacts with fewer GJK calls") {
  // Two knots, the tool walked through the scene in small steps (turning
  // and pressing, as the slow loop sees it), with jumps between far poses:
  // every query with the kept directions finds exactly what a query
  // without them finds, and the directions answer many piece tests.
  const std::string path =
      (std::filesystem::path(HAPTICBENCH_SOURCE_DIR) / "models/knot1.off").string();
  if (!std::filesystem::exists(path))
    FAIL(path << " is missing: run scripts/extract-models (CMake's configure step runs it)");
  const ConvexHierarchy knot =
      build_convex_hierarchy(read_mesh_file(path, 0.05), ConvexHierarchySettings{});
  const double size = 2 * knot.nodes[static_cast<std::size_t>(knot.root)].radius;
  const Pose scene_pose{Vec3(0.1, 0, 0), Quat(Eigen::AngleAxisd(0.4, Vec3::UnitY()))};
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> step(-0.004 * size, 0.004 * size), turn(-0.02, 0.02);
  std::uniform_real_distribution<double> jump(-0.2 * size, 0.2 * size);
  SeparatingAxes axes;
  Pose tool_pose{scene_pose.p + Vec3(0.1 * size, 0, 0.05 * size), random_rotation(rng)};
  int64_t by_axis = 0, piece_tests = 0, contacts_found = 0;
  for (const double margin : {0.0, 0.002 * size}) {
    const HierarchyContactSettings settings{0.05, margin};
    for (int query = 0; query < 20; ++query) {
      if (query % 10 == 9) {
        tool_pose.p = scene_pose.p + Vec3(jump(rng), jump(rng), jump(rng));
        tool_pose.q = random_rotation(rng);
      } else {
        tool_pose.p += Vec3(step(rng), step(rng), step(rng));
        tool_pose.q =
            (tool_pose.q * Quat(Eigen::AngleAxisd(turn(rng), Vec3::UnitZ()))).normalized();
      }
      std::vector<PieceContact> plain, kept;
      HierarchyContactStats plain_stats, kept_stats;
      find_hierarchy_contacts(knot, tool_pose, knot, scene_pose, settings, plain, plain_stats);
      find_hierarchy_contacts(knot, tool_pose, knot, scene_pose, settings, kept, kept_stats, &axes);
      INFO("margin " << margin << ", query " << query);
      const bool same_contacts = std::equal(kept.begin(), kept.end(), plain.begin(), plain.end(),
                                            [](const PieceContact& a, const PieceContact& b) {
                                              return a.tool_node == b.tool_node &&
                                                     a.scene_node == b.scene_node &&
                                                     a.point == b.point && a.normal == b.normal &&
                                                     a.depth == b.depth && a.gap_m == b.gap_m;
                                            });
      REQUIRE(same_contacts);
      CHECK(kept_stats.node_pairs_tested == plain_stats.node_pairs_tested);
      CHECK(kept_stats.piece_tests == plain_stats.piece_tests);
      CHECK(plain_stats.axis_separations == 0);
      by_axis += kept_stats.axis_separations;
      piece_tests += kept_stats.piece_tests;
      contacts_found += static_cast<int64_t>(kept.size());
    }
  }
  INFO(by_axis << " of " << piece_tests << " piece tests by a kept direction, " << contacts_found
               << " contacts");
  CHECK(contacts_found > 200);
  CHECK(by_axis > piece_tests / 10);
}

TEST_CASE("a contact query asked again allocates nothing: its buffers are kept") {
  // Overlaps that take each path: face on face (EPA, polishing, polygons
  // clipped), crossed edges (segments), a vertex on a face, and a gap
  // within the margin (GJK, features without EPA); then the hierarchy
  // traversal over them. The first call may size the buffers; the same
  // query again must not allocate.
  const double h = 0.5;
  const std::vector<Vec3> cube = box(Vec3(h, h, h));
  const std::vector<Vec3> slab = box(Vec3(0.2, 0.1, 0.1));
  const std::vector<Vec3> octahedron = {Vec3(0.1, 0, 0),  Vec3(-0.1, 0, 0), Vec3(0, 0.1, 0),
                                        Vec3(0, -0.1, 0), Vec3(0, 0, 0.1),  Vec3(0, 0, -0.1)};
  const double top = h * std::numbers::sqrt2;
  const std::vector<std::pair<PlacedConvex, PlacedConvex>> queries = {
      {PlacedConvex{cube, kPlacement},
       PlacedConvex{slab, kPlacement * make_pose(Vec3(0.1, -0.2, h + 0.1 - 0.03))}},
      {PlacedConvex{cube, kPlacement * make_pose(Vec3::Zero(), Vec3(0, std::numbers::pi / 4, 0))},
       PlacedConvex{cube, kPlacement * make_pose(Vec3(0, 0, 2 * top - 0.02),
                                                 Vec3(std::numbers::pi / 4, 0, 0))}},
      {PlacedConvex{cube, kPlacement},
       PlacedConvex{octahedron,
                    kPlacement * make_pose(Vec3(0.1, 0.2, h + 0.1 - 0.01), Vec3(0.1, 0.2, 0.3))}},
      {PlacedConvex{cube, kPlacement},
       PlacedConvex{slab, kPlacement * make_pose(Vec3(0.1, -0.2, h + 0.1 + 0.005))}},
  };
  for (std::size_t k = 0; k < queries.size(); ++k) {
    INFO("query " << k);
    const auto& [a, b] = queries[k];
    const ConvexProximity first = convex_proximity(a, b, 0.01);
    REQUIRE(first.in_contact);
    ConvexProximity again;
    CHECK(allocations_of([&] { again = convex_proximity(a, b, 0.01); }) == 0);
    CHECK(again.point == first.point);
    CHECK(again.normal == first.normal);
    CHECK(again.signed_depth == first.signed_depth);
  }
  // Checked to fail: a vector built inside the query allocates on every call.
  const std::vector<Vec3> fresh = {Vec3::Zero()};
  CHECK(allocations_of([&] { std::vector<Vec3> copy(fresh); }) == 1);

  const ConvexHierarchy scene = bridged_cubes();
  const ConvexHierarchy tool = two_level(box(Vec3(0.2, 0.2, 0.2), Vec3(-1, 0, 0)),
                                         box(Vec3(0.2, 0.2, 0.2), Vec3(1, 0, 0)), 0.01);
  const Pose tool_pose = kScenePose * make_pose(Vec3(0.05, 0.1, 0.5 + 0.2 - 0.02));
  std::vector<PieceContact> contacts;
  HierarchyContactStats stats;
  find_hierarchy_contacts(tool, tool_pose, scene, kScenePose, {0, 0.01}, contacts, stats);
  REQUIRE(contacts.size() >= 2);
  const std::size_t found = contacts.size();
  contacts.clear();
  CHECK(allocations_of([&] {
          find_hierarchy_contacts(tool, tool_pose, scene, kScenePose, {0, 0.01}, contacts, stats);
        }) == 0);
  CHECK(contacts.size() == found);
}

}  // namespace
}  // namespace hb
