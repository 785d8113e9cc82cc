#include "algorithms/ccd/mesh_ccd.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <tuple>

#include "algorithms/ccd/feature_places.h"
#include "algorithms/ccd/interval.h"
#include "algorithms/ccd/mesh_ccd_search.h"
#include "algorithms/ccd/mesh_features.h"
#include "algorithms/ccd/mesh_proximity.h"
#include "algorithms/ccd/screw_ccd.h"
#include "hapticbench/closest_points.h"
#include "hapticbench/input_error.h"

namespace hb {

using ccd_detail::MeshFeatures;

namespace {

std::string number_text(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

/// A unit vector perpendicular to v (the x axis when v is zero).
Vec3 any_perpendicular(const Vec3& v) {
  if (v.squaredNorm() == 0) return Vec3::UnitX();
  const Vec3 other = std::abs(v.x()) < std::abs(v.y()) ? Vec3::UnitX() : Vec3::UnitY();
  return v.cross(other).normalized();
}

/// Below this the sum of an edge's adjacent unit face normals counts as
/// zero (a knife edge, or faces folded onto each other).
constexpr double kNormalSumFloor = 1e-6;

FeatureGeometry vertex_face_geometry(const Vec3& vertex, const Vec3& a, const Vec3& b,
                                     const Vec3& c, const Vec3& unit_normal) {
  FeatureGeometry g;
  g.point = closest_point_on_triangle(vertex, a, b, c);
  g.distance = (vertex - g.point).norm();
  g.normal = unit_normal;
  if (g.normal.squaredNorm() == 0)  // degenerate face: away from it
    g.normal = g.distance > 0 ? Vec3((vertex - g.point) / g.distance) : Vec3::UnitZ();
  g.gap = (vertex - a).dot(g.normal);
  return g;
}

/// Edge (p0, p1) of the tool against edge (q0, q1) of the scene, world
/// frame; the normal sums orient the common normal.
FeatureGeometry edge_edge_geometry(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1,
                                   const Vec3& scene_normal_sum, const Vec3& tool_normal_sum) {
  FeatureGeometry g;
  const auto [on_tool, on_scene] = closest_points_of_segments(p0, p1, q0, q1);
  g.point = on_scene;
  g.distance = (on_tool - on_scene).norm();
  const Vec3 outward = scene_normal_sum.norm() > kNormalSumFloor  ? scene_normal_sum
                       : tool_normal_sum.norm() > kNormalSumFloor ? Vec3(-tool_normal_sum)
                                                                  : Vec3::Zero();
  const Vec3 d1 = p1 - p0, d2 = q1 - q0;
  Vec3 normal = d1.cross(d2);
  if (!(normal.norm() > 1e-9 * d1.norm() * d2.norm())) {
    // Parallel lines (or a zero-length edge): the lines' offset, the
    // difference of their closest points, is the common normal.
    const Vec3 along = d2.squaredNorm() > 0 ? d2 : d1;
    Vec3 offset = p0 - q0;
    if (along.squaredNorm() > 0) offset -= (offset.dot(along) / along.squaredNorm()) * along;
    if (!(offset.norm() > 1e-12 * std::max(p0.norm(), q0.norm()))) {
      // The lines coincide: the outward direction made perpendicular.
      offset = outward;
      if (along.squaredNorm() > 0) offset -= (offset.dot(along) / along.squaredNorm()) * along;
    }
    normal = offset.norm() > 0 ? offset : any_perpendicular(along);
  }
  normal.normalize();
  if (normal.dot(outward) < 0) normal = -normal;
  g.normal = normal;
  g.gap = (p0 - q0).dot(normal);
  return g;
}

Pose pose_at(const ScrewMotion& motion, double t) {
  return Pose{motion.point_at(Vec3::Zero(), t), Quat(motion.rotation_at(t)).normalized()};
}

}  // namespace

struct MeshCcd::Data {
  MeshFeatures tool;                 // tool frame
  std::vector<MeshFeatures> scene;   // world frame
  ccd_detail::FeaturePlaces places;  // of the scene's features
  double tool_radius = 0;
  bool all_cached = true;  // every mesh's features came from the disk cache
};

void validate_mesh_ccd_settings(const MeshCcdSettings& settings, const std::string& field_prefix) {
  validate_ccd_settings(settings.primitive, field_prefix + ".primitive");
  if (!(settings.contact_window >= 0 && settings.contact_window <= 1))
    throw InputError(
        "", field_prefix + ".contact_window",
        "expected a fraction of the step in [0, 1], got " + number_text(settings.contact_window));
}

MeshCcd::MeshCcd(const TriangleMesh& tool_mesh, std::span<const SceneObject> scene)
    : data_(std::make_unique<Data>()) {
  if (tool_mesh.triangles.empty())
    throw InputError("", "tool", "expected a tool mesh with at least one triangle");
  bool hit = false;
  data_->tool =
      ccd_detail::cached_mesh_features(tool_mesh.vertices, tool_mesh.triangles, "tool", &hit);
  data_->all_cached = hit;
  double largest = 0;
  for (const Vec3& v : data_->tool.vertices) largest = std::max(largest, v.norm());
  data_->tool_radius = next_up(largest * (1 + 1e-12));
  data_->scene.reserve(scene.size());
  for (std::size_t o = 0; o < scene.size(); ++o) {
    const SceneObject& object = scene[o];
    std::vector<Vec3> world(object.mesh.vertices.size());
    for (std::size_t v = 0; v < world.size(); ++v)
      world[v] = object.pose.transform_point(object.mesh.vertices[v]);
    const std::string name = object.name.empty() ? "scene[" + std::to_string(o) + "]" : object.name;
    data_->scene.push_back(
        ccd_detail::cached_mesh_features(std::move(world), object.mesh.triangles, name, &hit));
    data_->all_cached = data_->all_cached && hit;
  }
  data_->places = ccd_detail::FeaturePlaces(data_->scene);
}

bool MeshCcd::scene_features_share_places() const { return data_->places.any_shared(); }

bool MeshCcd::cache_hit() const { return data_->all_cached; }

MeshCcd::~MeshCcd() = default;
MeshCcd::MeshCcd(MeshCcd&&) noexcept = default;
MeshCcd& MeshCcd::operator=(MeshCcd&&) noexcept = default;

MeshCcdResult MeshCcd::first_contact(const ScrewMotion& motion,
                                     const MeshCcdSettings& settings) const {
  if (!motion.within(kMaxCcdCoordinate)) {
    MeshCcdResult result;
    result.contact = true;
    result.toi = 0;
    return result;
  }
  MeshCcdResult result =
      ccd_detail::search_first_contact(data_->tool, data_->scene, motion, settings);
  if (!result.contacts.empty()) {
    const Pose pose = pose_at(motion, result.toi);
    for (MeshCcdContact& contact : result.contacts)
      contact.geometry = evaluate(contact.features, pose);
  }
  return result;
}

namespace {
const MeshFeatures& checked_scene(const MeshFeatures& tool, std::span<const MeshFeatures> scenes,
                                  const ContactFeatures& features);
}  // namespace

MeshCcdResult MeshCcd::first_contact_among(const ScrewMotion& motion,
                                           std::span<const ContactFeatures> pairs,
                                           const MeshCcdSettings& settings) const {
  MeshCcdResult result;
  if (!motion.within(kMaxCcdCoordinate)) {
    result.contact = true;
    result.toi = 0;
    return result;
  }
  const MeshFeatures& tool = data_->tool;
  const double cap =
      !(settings.primitive.time_limit < 1) ? 1.0 : std::max(settings.primitive.time_limit, 0.0);
  const double window = settings.contact_window >= 0 ? std::min(settings.contact_window, 1.0) : 0.0;
  CcdSettings kernel = settings.primitive;
  kernel.time_limit = cap;
  std::vector<MeshCcdContact> candidates;
  double best = 2;  // above every toi
  for (const ContactFeatures& features : pairs) {
    const MeshFeatures& scene = checked_scene(tool, data_->scene, features);
    CcdResult r;
    switch (features.kind) {
      case ContactFeatureKind::kToolVertexSceneFace: {
        const auto& tri = scene.triangle(features.scene_feature);
        r = screw_vertex_face_ccd(
            motion, tool.vertex(features.tool_feature),
            {scene.vertex(tri[0]), scene.vertex(tri[1]), scene.vertex(tri[2])}, kernel);
        break;
      }
      case ContactFeatureKind::kSceneVertexToolFace: {
        const auto& tri = tool.triangle(features.tool_feature);
        r = screw_face_vertex_ccd(motion,
                                  {tool.vertex(tri[0]), tool.vertex(tri[1]), tool.vertex(tri[2])},
                                  scene.vertex(features.scene_feature), kernel);
        break;
      }
      case ContactFeatureKind::kEdgeEdge: {
        const auto& te = tool.edge(features.tool_feature);
        const auto& se = scene.edge(features.scene_feature);
        r = screw_edge_edge_ccd(motion, {tool.vertex(te[0]), tool.vertex(te[1])},
                                {scene.vertex(se[0]), scene.vertex(se[1])}, kernel);
        break;
      }
    }
    ++result.primitive_queries;
    result.primitive_evaluations += r.evaluations;
    result.budget_exhausted = result.budget_exhausted || r.budget_exhausted;
    if (!r.contact) continue;
    candidates.push_back(MeshCcdContact{features, r.toi, {}});
    if (r.toi < best) {
      best = r.toi;
      kernel.time_limit = std::min(cap, best + window);  // later pairs search only up to it
    }
  }
  if (candidates.empty()) return result;
  result.contact = true;
  result.toi = best;
  const Pose pose = pose_at(motion, best);
  for (MeshCcdContact& contact : candidates)
    if (contact.toi <= best + window) {
      contact.geometry = evaluate(contact.features, pose);
      result.contacts.push_back(contact);
    }
  std::stable_sort(result.contacts.begin(), result.contacts.end(),
                   [](const MeshCcdContact& x, const MeshCcdContact& y) { return x.toi < y.toi; });
  return result;
}

namespace {
// How many features a pair's tool_feature and scene_feature index, by kind
// ({0, 0} for a kind that names none).
std::array<std::size_t, 2> feature_counts(const MeshFeatures& tool, const MeshFeatures& scene,
                                          ContactFeatureKind kind) {
  switch (kind) {
    case ContactFeatureKind::kToolVertexSceneFace:
      return {tool.vertices.size(), scene.triangles.size()};
    case ContactFeatureKind::kSceneVertexToolFace:
      return {tool.triangles.size(), scene.vertices.size()};
    case ContactFeatureKind::kEdgeEdge:
      return {tool.edges.size(), scene.edges.size()};
  }
  return {0, 0};
}

bool within(int index, std::size_t size) {
  return index >= 0 && static_cast<std::size_t>(index) < size;
}

// Throws InputError naming the first index of `features` out of range.
[[noreturn]] [[gnu::cold]] void throw_out_of_range(const MeshFeatures& tool,
                                                   std::span<const MeshFeatures> scenes,
                                                   const ContactFeatures& features) {
  if (!within(features.scene_object, scenes.size()))
    throw InputError("", "features.scene_object",
                     "no scene object " + std::to_string(features.scene_object));
  if (features.kind != ContactFeatureKind::kToolVertexSceneFace &&
      features.kind != ContactFeatureKind::kSceneVertexToolFace &&
      features.kind != ContactFeatureKind::kEdgeEdge)
    throw InputError("", "features.kind", "unknown feature pair kind");
  const auto counts =
      feature_counts(tool, scenes[static_cast<std::size_t>(features.scene_object)], features.kind);
  for (const auto& [index, count, field] :
       {std::tuple{features.tool_feature, counts[0], "tool_feature"},
        std::tuple{features.scene_feature, counts[1], "scene_feature"}})
    if (!within(index, count))
      throw InputError(
          "", std::string("features.") + field,
          "index " + std::to_string(index) + " out of range [0, " + std::to_string(count) + ")");
  throw InputError("", "features", "indices in range reported out of range");
}

// The scene object of a feature pair, with the pair's indices checked
// (InputError naming the field otherwise).
const MeshFeatures& checked_scene(const MeshFeatures& tool, std::span<const MeshFeatures> scenes,
                                  const ContactFeatures& features) {
  if (!within(features.scene_object, scenes.size())) throw_out_of_range(tool, scenes, features);
  const MeshFeatures& scene = scenes[static_cast<std::size_t>(features.scene_object)];
  const auto counts = feature_counts(tool, scene, features.kind);
  if (!within(features.tool_feature, counts[0]) || !within(features.scene_feature, counts[1]))
    throw_out_of_range(tool, scenes, features);
  return scene;
}

/// Calls visit(i, scene, rotation, place) for every pair i at `tool_pose`:
/// its scene object (indices checked), the tool's rotation and place(v),
/// tool vertex v in the world. From PlacedToolVertices::kFewPairs pairs on,
/// each vertex is placed once.
template <class Visit>
void visit_at_pose(const MeshFeatures& tool, std::span<const MeshFeatures> scenes,
                   std::span<const ContactFeatures> pairs, const Pose& tool_pose, Visit&& visit) {
  const Mat3 rotation = tool_pose.q.normalized().toRotationMatrix();
  if (pairs.size() < ccd_detail::PlacedToolVertices::kFewPairs) {
    auto place = [&](int v) -> Vec3 {
      return ccd_detail::placed_vertex(tool, rotation, tool_pose.p, v);
    };
    for (std::size_t i = 0; i < pairs.size(); ++i)
      visit(i, checked_scene(tool, scenes, pairs[i]), rotation, place);
    return;
  }
  ccd_detail::PlacedToolVertices placed(tool, rotation, tool_pose.p);
  auto place = [&](int v) -> Vec3 { return placed(v); };
  for (std::size_t i = 0; i < pairs.size(); ++i)
    visit(i, checked_scene(tool, scenes, pairs[i]), rotation, place);
}
}  // namespace

ProximityResult MeshCcd::proximity(const Pose& tool_pose, double max_distance,
                                   std::size_t max_pairs) const {
  return ccd_detail::search_proximity(data_->tool, data_->scene, tool_pose, max_distance,
                                      max_pairs);
}

ProximityInSlices MeshCcd::start_proximity(const Pose& tool_pose, double max_distance,
                                           std::size_t max_pairs) const {
  return ProximityInSlices(ccd_detail::start_proximity_search(data_->tool, data_->scene, tool_pose,
                                                              max_distance, max_pairs));
}

PairClosestPoints MeshCcd::closest_points(const ContactFeatures& features,
                                          const Pose& tool_pose) const {
  return ccd_detail::pair_closest_points(
      data_->tool, checked_scene(data_->tool, data_->scene, features), features,
      tool_pose.q.normalized().toRotationMatrix(), tool_pose.p);
}

void MeshCcd::scene_feature_places(std::span<const ContactFeatures> pairs,
                                   std::vector<int>& places) const {
  places.assign(pairs.size(), -1);
  if (!data_->places.any_shared()) return;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    checked_scene(data_->tool, data_->scene, pairs[i]);
    places[i] = data_->places.place(pairs[i]);
  }
}

void MeshCcd::closest_points(std::span<const ContactFeatures> pairs, const Pose& tool_pose,
                             std::vector<PairClosestPoints>& points) const {
  points.resize(pairs.size());
  visit_at_pose(data_->tool, data_->scene, pairs, tool_pose,
                [&](std::size_t i, const MeshFeatures& scene, const Mat3&, auto&& place) {
                  points[i] =
                      ccd_detail::pair_closest_points_placed(data_->tool, scene, pairs[i], place);
                });
}

namespace {

/// The pair's geometry, the tool's vertex v placed in the world by
/// place(v) and its directions turned by `rotation` (indices already checked).
template <class Place>
FeatureGeometry geometry_placed(const MeshFeatures& tool, const MeshFeatures& scene,
                                const ContactFeatures& features, const Mat3& rotation,
                                Place&& place) {
  switch (features.kind) {
    case ContactFeatureKind::kToolVertexSceneFace: {
      const auto& tri = scene.triangle(features.scene_feature);
      return vertex_face_geometry(
          place(features.tool_feature), scene.vertex(tri[0]), scene.vertex(tri[1]),
          scene.vertex(tri[2]),
          scene.face_normals[static_cast<std::size_t>(features.scene_feature)]);
    }
    case ContactFeatureKind::kSceneVertexToolFace: {
      const auto& tri = tool.triangle(features.tool_feature);
      const Vec3 a = place(tri[0]), b = place(tri[1]), c = place(tri[2]);
      const Vec3& vertex = scene.vertex(features.scene_feature);
      const Vec3 tool_normal =
          rotation * tool.face_normals[static_cast<std::size_t>(features.tool_feature)];
      FeatureGeometry g;
      g.point = vertex;
      const Vec3 on_face = closest_point_on_triangle(vertex, a, b, c);
      g.distance = (vertex - on_face).norm();
      g.normal = -tool_normal;
      if (tool_normal.squaredNorm() == 0)  // degenerate face: from the vertex to it
        g.normal = g.distance > 0 ? Vec3((on_face - vertex) / g.distance) : Vec3::UnitZ();
      g.gap = (a - vertex).dot(g.normal);
      return g;
    }
    case ContactFeatureKind::kEdgeEdge: {
      const auto& te = tool.edge(features.tool_feature);
      const auto& se = scene.edge(features.scene_feature);
      return edge_edge_geometry(place(te[0]), place(te[1]), scene.vertex(se[0]),
                                scene.vertex(se[1]), scene.edge_normal_sum(features.scene_feature),
                                rotation * tool.edge_normal_sum(features.tool_feature));
    }
  }
  return {};
}

}  // namespace

FeatureGeometry MeshCcd::evaluate(const ContactFeatures& features, const Pose& tool_pose) const {
  const MeshFeatures& tool = data_->tool;
  const MeshFeatures& scene = checked_scene(tool, data_->scene, features);
  const Mat3 rotation = tool_pose.q.normalized().toRotationMatrix();
  return geometry_placed(tool, scene, features, rotation, [&](int v) -> Vec3 {
    return ccd_detail::placed_vertex(tool, rotation, tool_pose.p, v);
  });
}

void MeshCcd::evaluate(std::span<const ContactFeatures> pairs, const Pose& tool_pose,
                       std::vector<FeatureGeometry>& geometry) const {
  geometry.resize(pairs.size());
  visit_at_pose(data_->tool, data_->scene, pairs, tool_pose,
                [&](std::size_t i, const MeshFeatures& scene, const Mat3& rotation, auto&& place) {
                  geometry[i] = geometry_placed(data_->tool, scene, pairs[i], rotation, place);
                });
}

std::span<const std::array<int, 2>> MeshCcd::tool_edges() const { return data_->tool.edges; }

std::span<const std::array<int, 2>> MeshCcd::scene_edges(int object) const {
  if (object < 0 || static_cast<std::size_t>(object) >= data_->scene.size())
    throw InputError("", "object", "no scene object " + std::to_string(object));
  return data_->scene[static_cast<std::size_t>(object)].edges;
}

std::pair<Vec3, double> MeshCcd::scene_bounding_sphere() const {
  std::pair<Vec3, double> bound{Vec3::Zero(), -1.0};
  for (const MeshFeatures& object : data_->scene) {
    if (object.tree.empty()) continue;
    const SphereTreeNode& root = object.node(0);
    if (bound.second < 0) bound = {root.centre, root.radius};
    bound.second = std::max(
        bound.second, next_up(((root.centre - bound.first).norm() + root.radius) * (1 + 1e-12)));
  }
  return bound;
}

double MeshCcd::tool_radius() const { return data_->tool_radius; }

std::size_t MeshCcd::memory_bytes() const {
  std::size_t bytes = sizeof(Data) + data_->tool.memory_bytes();
  for (const MeshFeatures& object : data_->scene) bytes += object.memory_bytes();
  return bytes;
}

}  // namespace hb
