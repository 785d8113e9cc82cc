// The Embree ground-truth backend: Embree's float BVH finds candidate
// triangles, and every answer is recomputed from the double-precision world
// vertices, so distances and closest points match an exact double
// computation. Inside/outside is ray parity per closed object: two rays in
// fixed directions must agree, and more directions are tried when they
// disagree or a ray passes too close to an edge or vertex.
// Every Embree header of the project stays in this file. Coordinates are
// metres, world frame.
#include <embree3/rtcore.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <new>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

#include "algorithms/core/build_progress.h"
#include "hapticbench/closest_points.h"
#include "hapticbench/input_error.h"
#include "harness/process/memory_limit.h"
#include "harness/reference/oracle.h"

namespace hb {
namespace {

// Parity rays: fixed, deterministic and deliberately not aligned with any
// axis or diagonal, so axis-aligned meshes and grid-sampled points do not
// line up with them. The first is tried first for every point.
constexpr std::array<std::array<double, 3>, 8> kParityDirections = {{
    {0.5377, 0.6189, 0.5723},
    {-0.7071, 0.3090, 0.6360},
    {0.2910, -0.8413, 0.4556},
    {-0.3827, -0.4339, -0.8155},
    {0.8660, 0.1736, -0.4690},
    {-0.5592, 0.7431, -0.3676},
    {0.1045, -0.2588, 0.9603},
    {-0.9135, -0.3584, 0.1925},
}};

// A hit is too close to call when its barycentric coordinates are within
// this of an edge, or when the ray is this close to the triangle's plane
// (|cos| between ray and normal): a ray through an edge or vertex can be
// counted twice or not at all.
constexpr double kEdgeMargin = 1e-6;
constexpr double kGrazingCosine = 1e-6;

// One scene object in the world frame, double precision. Indexed, not a
// triangle soup: the smaller working set is faster for closest points.
struct WorldObject {
  std::vector<Vec3> vertices;                 // m, world frame
  std::vector<std::array<int, 3>> triangles;  // CCW seen from outside
  Eigen::AlignedBox3d bounds;                 // m, world frame
  bool closed = false;                        // used for inside/outside

  const Vec3& corner(unsigned triangle, int k) const { return vertices[triangles[triangle][k]]; }
};

// What the parity filter records during one ray cast.
struct ParityState {
  const std::vector<WorldObject>* objects = nullptr;
  Vec3 origin;                    // m, the query point (double)
  Vec3 direction;                 // unit, exactly the float ray's direction
  std::vector<uint8_t> relevant;  // per object: closed and its bounds hold the point
  std::vector<uint8_t> parity;    // per object: crossings so far, mod 2
  std::vector<std::pair<unsigned, unsigned>> seen;  // (geomID, primID) already counted
  bool degenerate = false;                          // some crossing was too close to call
};

// Embree hands the filter the RTCIntersectContext it was given: with the
// context as first member of a standard-layout struct, the filter recovers
// the state from it.
struct ParityCast {
  RTCIntersectContext embree;
  ParityState* state;
};
static_assert(std::is_standard_layout_v<ParityCast>);

// Intersection filter: records the crossing and rejects the hit, so
// traversal goes on and every crossing along the ray is seen.
void count_crossing(const RTCFilterFunctionNArguments* args) {
  ParityState* state = reinterpret_cast<ParityCast*>(args->context)->state;
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    args->valid[i] = 0;
    const unsigned geom = RTCHitN_geomID(args->hit, args->N, i);
    const unsigned prim = RTCHitN_primID(args->hit, args->N, i);
    if (!state->relevant[geom]) continue;
    // A triangle referenced from several BVH leaves may be reported more
    // than once; it is crossed once.
    const std::pair<unsigned, unsigned> key(geom, prim);
    if (std::find(state->seen.begin(), state->seen.end(), key) != state->seen.end()) continue;
    state->seen.push_back(key);
    state->parity[geom] ^= 1;

    // Recompute the crossing in double (Moller-Trumbore) on the exact
    // vertices: a hit near an edge or vertex, a grazing hit, or one the
    // double test places behind the origin, makes the cast unreliable.
    const WorldObject& object = (*state->objects)[geom];
    const Vec3& a = object.corner(prim, 0);
    const Vec3 e1 = object.corner(prim, 1) - a;
    const Vec3 e2 = object.corner(prim, 2) - a;
    const Vec3 p = state->direction.cross(e2);
    const double det = e1.dot(p);
    const double area2 = e1.cross(e2).norm();
    if (!(std::abs(det) > kGrazingCosine * area2)) {
      state->degenerate = true;
      continue;
    }
    const Vec3 s = state->origin - a;
    const Vec3 q = s.cross(e1);
    const double u = s.dot(p) / det;
    const double v = state->direction.dot(q) / det;
    const double t = e2.dot(q) / det;
    if (!(u > kEdgeMargin && v > kEdgeMargin && 1 - u - v > kEdgeMargin && t > 0))
      state->degenerate = true;
  }
}

// State of one closest-point search, handed to the point-query callback.
struct ClosestSearch {
  const std::vector<WorldObject>* objects = nullptr;
  Vec3 point;        // m, query point (double)
  double slack = 0;  // m, margin for Embree's float culling
  double best_distance_sq = std::numeric_limits<double>::infinity();
  Vec3 best_point;  // m
  int32_t best_object = -1;
  unsigned best_triangle = 0;
};

// Point-query callback: exact double distance to the candidate triangle;
// shrinks the query sphere when it found a nearer one. The sphere keeps a
// margin over the double distance because Embree culls with float bounds
// of float vertices around a float query point.
bool visit_candidate(RTCPointQueryFunctionArguments* args) {
  auto* search = static_cast<ClosestSearch*>(args->userPtr);
  const WorldObject& object = (*search->objects)[args->geomID];
  const Vec3 closest =
      closest_point_on_triangle(search->point, object.corner(args->primID, 0),
                                object.corner(args->primID, 1), object.corner(args->primID, 2));
  const double distance_sq = (closest - search->point).squaredNorm();
  if (!(distance_sq < search->best_distance_sq)) return false;
  search->best_distance_sq = distance_sq;
  search->best_point = closest;
  search->best_object = static_cast<int32_t>(args->geomID);
  search->best_triangle = args->primID;
  const float radius = std::nextafter(static_cast<float>(std::sqrt(distance_sq) + search->slack),
                                      std::numeric_limits<float>::infinity());
  if (radius >= args->query->radius) return false;
  args->query->radius = radius;
  return true;
}

// State of a search for every triangle within a radius.
struct RadiusSearch {
  const std::vector<WorldObject>* objects = nullptr;
  Vec3 point;         // m, query point (double)
  double radius = 0;  // m, exact double radius
  std::vector<NearTriangle>* found = nullptr;
  std::vector<std::pair<unsigned, unsigned>> seen;  // (geomID, primID) already reported
};

// Point-query callback: keeps a candidate whose exact double distance is
// within the radius; the query sphere (float, with slack) never shrinks.
bool collect_candidate(RTCPointQueryFunctionArguments* args) {
  auto* search = static_cast<RadiusSearch*>(args->userPtr);
  const WorldObject& object = (*search->objects)[args->geomID];
  const std::array<Vec3, 3> corners = {object.corner(args->primID, 0),
                                       object.corner(args->primID, 1),
                                       object.corner(args->primID, 2)};
  const Vec3 closest = closest_point_on_triangle(search->point, corners[0], corners[1], corners[2]);
  const double distance = (closest - search->point).norm();
  if (!(distance <= search->radius)) return false;
  // A triangle referenced from several BVH leaves may be visited twice.
  const std::pair<unsigned, unsigned> key(args->geomID, args->primID);
  if (std::find(search->seen.begin(), search->seen.end(), key) != search->seen.end()) return false;
  search->seen.push_back(key);
  search->found->push_back({closest, distance, static_cast<int32_t>(args->geomID), corners});
  return false;
}

// Spreads the low 21 bits of x to every third bit (for a 63-bit Morton code).
uint64_t spread_bits(uint64_t x) {
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}

// The same surface with triangles in Morton order of their centroids and
// vertices numbered by first use: the triangles of one BVH leaf, and of
// neighbouring leaves, then sit together in memory, so a query touches
// few cache lines. Which triangle is which is never reported.
TriangleMesh in_spatial_order(const TriangleMesh& mesh) {
  const Eigen::AlignedBox3d box = mesh.bounds();
  const Vec3 extent = box.sizes().cwiseMax(std::numeric_limits<double>::min());
  std::vector<std::pair<uint64_t, std::size_t>> order(mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& [a, b, c] = mesh.triangles[t];
    const Vec3 centroid = (mesh.vertices[a] + mesh.vertices[b] + mesh.vertices[c]) / 3;
    uint64_t code = 0;
    for (int axis = 0; axis < 3; ++axis) {
      const double f = std::clamp((centroid[axis] - box.min()[axis]) / extent[axis], 0.0, 1.0);
      code |= spread_bits(static_cast<uint64_t>(f * 2097151.0)) << axis;
    }
    order[t] = {code, t};
  }
  std::sort(order.begin(), order.end());
  TriangleMesh result;
  result.triangles.reserve(mesh.triangles.size());
  result.vertices.reserve(mesh.vertices.size());
  std::vector<int> new_index(mesh.vertices.size(), -1);
  for (const auto& [code, t] : order) {
    std::array<int, 3> triangle;
    for (int k = 0; k < 3; ++k) {
      int& index = new_index[static_cast<std::size_t>(mesh.triangles[t][k])];
      if (index < 0) {
        index = static_cast<int>(result.vertices.size());
        result.vertices.push_back(mesh.vertices[static_cast<std::size_t>(mesh.triangles[t][k])]);
      }
      triangle[k] = index;
    }
    result.triangles.push_back(triangle);
  }
  return result;
}

// Owning handles: released however construction or use ends.
struct ReleaseDevice {
  void operator()(RTCDevice device) const { rtcReleaseDevice(device); }
};
struct ReleaseScene {
  void operator()(RTCScene scene) const { rtcReleaseScene(scene); }
};
using EmbreeDevice = std::unique_ptr<RTCDeviceTy, ReleaseDevice>;
using EmbreeScene = std::unique_ptr<RTCSceneTy, ReleaseScene>;

class EmbreeOracle final : public Oracle {
 public:
  explicit EmbreeOracle(const std::vector<SceneObject>& scene) {
    // Embree's start-up reservations are its own, not the scene's: made
    // outside the memory ceiling (harness/process/memory_limit.h).
    outside_memory_limit([&] { device_.reset(rtcNewDevice(nullptr)); });
    if (!device_) {
      // Under the memory ceiling, Embree's thread pool and allocator may be
      // refused their reservations: that is memory, not a bug.
      if (rtcGetDeviceError(nullptr) == RTC_ERROR_OUT_OF_MEMORY) throw std::bad_alloc();
      throw std::runtime_error("Embree: cannot create a device");
    }
    scene_.reset(rtcNewScene(device_.get()));
    // Robust mode: traversal and triangle tests that do not trade accuracy
    // for speed, so fewer rays slip through shared edges.
    rtcSetSceneFlags(scene_.get(), RTC_SCENE_FLAG_ROBUST);
    // Embree's build asks this between its steps: false cancels it, so a
    // stop request ends a build of millions of triangles within moments.
    rtcSetSceneProgressMonitorFunction(
        scene_.get(), [](void*, double) { return !build_stop_requested(); }, nullptr);

    objects_.resize(scene.size());
    for (std::size_t i = 0; i < scene.size(); ++i) {
      const SceneObject& object = scene[i];
      const std::string location = "/scene/" + std::to_string(i);
      TriangleMesh world = transformed(object.mesh, object.pose);
      if (object.distance_only) {
        // Open or self-intersecting is allowed; the triangles must still be
        // readable (indices in range, finite, not degenerate).
        if (auto defect = find_mesh_defect(world, MeshRequirement::kSurface))
          throw InputError(object.name, location, defect->location + ": " + defect->message);
        distance_only_.push_back(object.name);
      } else if (auto why = inside_outside_defect(world)) {
        throw InputError(object.name, location,
                         *why +
                             "; inside/outside would be meaningless (mark the object "
                             "\"distance_only\": true to use it for distances only)");
      }
      check_build_stop();
      world = in_spatial_order(world);
      WorldObject& target = objects_[i];
      target.bounds = world.bounds();
      target.closed = !object.distance_only;
      add_embree_geometry(world, static_cast<unsigned>(i));
      target.vertices = std::move(world.vertices);
      target.triangles = std::move(world.triangles);
      bounds_.extend(target.bounds);
      if (target.closed) closed_bounds_.extend(target.bounds);
      if (!target.triangles.empty()) has_triangles_ = true;
    }
    rtcCommitScene(scene_.get());
    check_build_stop();  // a cancelled build ends here
    if (const RTCError error = rtcGetDeviceError(device_.get()); error != RTC_ERROR_NONE)
      throw std::runtime_error("Embree: building the scene failed (error " +
                               std::to_string(static_cast<int>(error)) + ")");
    if (!bounds_.isEmpty())
      coordinate_scale_ =
          std::max(bounds_.min().cwiseAbs().maxCoeff(), bounds_.max().cwiseAbs().maxCoeff());
    for (const auto& d : kParityDirections)
      directions_.push_back(Vec3(d[0], d[1], d[2]).normalized().cast<float>().cast<double>());
  }

  std::string_view name() const override { return "embree"; }

  void query_points(const PointQueryRequest& request, PointQueryResult& result) const override {
    const std::size_t n = request.points.size();
    if (request.want_inside) {
      result.inside.resize(n);
      // Scratch for every ray of this call: no allocation per point.
      ParityState state;
      state.objects = &objects_;
      state.relevant.resize(objects_.size());
      state.parity.resize(objects_.size());
      state.seen.reserve(64);
      for (std::size_t k = 0; k < n; ++k) result.inside[k] = is_inside(request.points[k], state);
    }
    if (request.want_closest) {
      result.resize_closest(n);
      for (std::size_t k = 0; k < n; ++k) {
        const Vec3& p = request.points[k];
        if (!has_triangles_ || !p.allFinite()) {  // nothing to be close to, or no point
          result.distance[k] = has_triangles_ ? std::numeric_limits<double>::quiet_NaN()
                                              : std::numeric_limits<double>::infinity();
          result.closest[k] = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
          result.normal[k] = Vec3::Zero();
          result.object[k] = -1;
          continue;
        }
        const ClosestSearch search = nearest_triangle(p, request.max_distance);
        if (search.best_object < 0 ||
            search.best_distance_sq > request.max_distance * request.max_distance) {
          result.distance[k] = request.max_distance;  // nothing nearer (or no triangle at all)
          result.closest[k] = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
          result.normal[k] = Vec3::Zero();
          result.object[k] = -1;
          continue;
        }
        const WorldObject& object = objects_[static_cast<std::size_t>(search.best_object)];
        const Vec3& a = object.corner(search.best_triangle, 0);
        result.distance[k] = std::sqrt(search.best_distance_sq);
        result.closest[k] = search.best_point;
        result.normal[k] = (object.corner(search.best_triangle, 1) - a)
                               .cross(object.corner(search.best_triangle, 2) - a)
                               .normalized();
        result.object[k] = search.best_object;
      }
    }
  }

  bool triangles_within(const Vec3& point, double radius_m,
                        std::vector<NearTriangle>& out) const override {
    out.clear();
    if (!has_triangles_ || !point.allFinite() || !(radius_m >= 0)) return true;
    RadiusSearch search;
    search.objects = &objects_;
    search.point = point;
    search.radius = radius_m;
    search.found = &out;
    const double slack = 1e-6 * (coordinate_scale_ + point.cwiseAbs().maxCoeff());
    RTCPointQuery query;
    query.x = static_cast<float>(point.x());
    query.y = static_cast<float>(point.y());
    query.z = static_cast<float>(point.z());
    query.time = 0;
    query.radius = std::nextafter(static_cast<float>(radius_m + slack),
                                  std::numeric_limits<float>::infinity());
    RTCPointQueryContext context;
    rtcInitPointQueryContext(&context);
    rtcPointQuery(scene_.get(), &query, &context, &collect_candidate, &search);
    return true;
  }

  std::optional<double> intersection_volume(const TriangleMesh&) const override {
    return std::nullopt;  // Embree has no solid operations
  }

  const std::vector<std::string>& distance_only_objects() const override { return distance_only_; }

  Eigen::AlignedBox3d bounds() const override { return bounds_; }

 private:
  // One Embree triangle geometry (float copy of the world mesh) with ID =
  // the object's scene index.
  void add_embree_geometry(const TriangleMesh& world, unsigned id) {
    if (world.triangles.empty()) return;
    RTCGeometry geometry = rtcNewGeometry(device_.get(), RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertices = static_cast<float*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                3 * sizeof(float), world.vertices.size()));
    auto* indices = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                3 * sizeof(unsigned), world.triangles.size()));
    if (!vertices || !indices) {
      rtcReleaseGeometry(geometry);
      throw std::runtime_error("Embree: cannot allocate buffers for " +
                               std::to_string(world.triangles.size()) + " triangles");
    }
    for (std::size_t v = 0; v < world.vertices.size(); ++v)
      for (int axis = 0; axis < 3; ++axis)
        vertices[3 * v + axis] = static_cast<float>(world.vertices[v][axis]);
    for (std::size_t t = 0; t < world.triangles.size(); ++t)
      for (int corner = 0; corner < 3; ++corner)
        indices[3 * t + corner] = static_cast<unsigned>(world.triangles[t][corner]);
    // Every geometry rejects its hits (after counting them when they
    // matter): an accepted hit would shorten the ray and hide crossings.
    rtcSetGeometryIntersectFilterFunction(geometry, &count_crossing);
    rtcCommitGeometry(geometry);
    rtcAttachGeometryByID(scene_.get(), geometry, id);
    rtcReleaseGeometry(geometry);
  }

  // Inside any closed object, by the parity of ray crossings. A cast is
  // clean when none of its crossings is too close to call. One clean cast
  // is not enough: Embree can lose a ray that passes within float rounding
  // of a vertex or edge without reporting any triangle there, which no hit
  // reveals. Two clean casts in different directions that agree decide;
  // otherwise the majority of the clean casts over all directions, then of
  // all casts, then outside.
  bool is_inside(const Vec3& p, ParityState& state) const {
    if (!closed_bounds_.contains(p)) return false;  // also rejects NaN
    bool any_relevant = false;
    for (std::size_t i = 0; i < objects_.size(); ++i) {
      state.relevant[i] = objects_[i].closed && objects_[i].bounds.contains(p);
      any_relevant = any_relevant || state.relevant[i];
    }
    if (!any_relevant) return false;

    state.origin = p;
    int casts = 0, inside_casts = 0;
    int clean = 0, inside_clean = 0;
    for (const Vec3& direction : directions_) {
      const bool inside = cast_parity_ray(state, direction);
      ++casts;
      inside_casts += inside ? 1 : 0;
      if (state.degenerate) continue;
      ++clean;
      inside_clean += inside ? 1 : 0;
      if (clean == 2 && inside_clean != 1) return inside;
    }
    if (2 * inside_clean != clean) return 2 * inside_clean > clean;
    return 2 * inside_casts > casts;
  }

  // One ray from state.origin; true when it crosses some relevant object an
  // odd number of times. Sets state.degenerate when a crossing was unsure.
  bool cast_parity_ray(ParityState& state, const Vec3& direction) const {
    ParityCast cast;
    rtcInitIntersectContext(&cast.embree);
    cast.state = &state;
    state.direction = direction;
    std::fill(state.parity.begin(), state.parity.end(), 0);
    state.seen.clear();
    state.degenerate = false;

    RTCRayHit ray_hit;
    ray_hit.ray.org_x = static_cast<float>(state.origin.x());
    ray_hit.ray.org_y = static_cast<float>(state.origin.y());
    ray_hit.ray.org_z = static_cast<float>(state.origin.z());
    ray_hit.ray.dir_x = static_cast<float>(direction.x());
    ray_hit.ray.dir_y = static_cast<float>(direction.y());
    ray_hit.ray.dir_z = static_cast<float>(direction.z());
    ray_hit.ray.tnear = 0;
    ray_hit.ray.tfar = std::numeric_limits<float>::infinity();
    ray_hit.ray.time = 0;
    ray_hit.ray.mask = 0xFFFFFFFFu;
    ray_hit.ray.id = 0;
    ray_hit.ray.flags = 0;
    ray_hit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    ray_hit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene_.get(), &cast.embree, &ray_hit);

    for (std::size_t i = 0; i < objects_.size(); ++i)
      if (state.relevant[i] && state.parity[i]) return true;
    return false;
  }

  // The nearest triangle within max_distance (m; none found beyond it).
  ClosestSearch nearest_triangle(const Vec3& p, double max_distance) const {
    ClosestSearch search;
    search.objects = &objects_;
    search.point = p;
    // Float rounding of vertices, bounds and the query point: a few ulps of
    // the largest coordinate involved, generously.
    search.slack = 1e-6 * (coordinate_scale_ + p.cwiseAbs().maxCoeff());
    RTCPointQuery query;
    query.x = static_cast<float>(p.x());
    query.y = static_cast<float>(p.y());
    query.z = static_cast<float>(p.z());
    query.time = 0;
    query.radius = std::isfinite(max_distance)
                       ? std::nextafter(static_cast<float>(max_distance + search.slack),
                                        std::numeric_limits<float>::infinity())
                       : std::numeric_limits<float>::infinity();
    RTCPointQueryContext context;
    rtcInitPointQueryContext(&context);
    rtcPointQuery(scene_.get(), &query, &context, &visit_candidate, &search);
    return search;
  }

  std::vector<WorldObject> objects_;  // index = scene index = Embree geomID
  std::vector<Vec3> directions_;      // parity rays, unit, float-exact
  std::vector<std::string> distance_only_;
  Eigen::AlignedBox3d bounds_;         // m, every object
  Eigen::AlignedBox3d closed_bounds_;  // m, objects used for inside/outside
  double coordinate_scale_ = 0;        // m, largest |coordinate| of the scene
  bool has_triangles_ = false;
  EmbreeDevice device_;  // declared before the scene: released after it
  EmbreeScene scene_;
};

}  // namespace

std::unique_ptr<Oracle> make_embree_oracle(const std::vector<SceneObject>& scene) {
  return std::make_unique<EmbreeOracle>(scene);
}

}  // namespace hb
