// Scene features at one place: tiles laid edge to edge share their corner
// vertices (and the triangles and edges between shared corners), and a
// feature's place is shared by exactly the features of its kind whose
// vertices have the same coordinates, in the same order.
#include "algorithms/ccd/feature_places.h"

#include <catch2/catch.hpp>
#include <vector>

#include "algorithms/ccd/mesh_ccd.h"
#include "hapticbench/shapes.h"
#include "tests/support/proxy_fixtures.h"

namespace hb {
namespace {

std::vector<SceneObject> tiles(int n, double gap) { return test::box_tiles(n, 0.01, gap); }

// The scene feature of a pair of `kind`, as its vertices' world coordinates.
std::vector<Vec3> scene_feature_vertices(const std::vector<SceneObject>& scene, const MeshCcd& ccd,
                                         const ContactFeatures& pair) {
  const SceneObject& object = scene[static_cast<std::size_t>(pair.scene_object)];
  const auto world = [&](int v) {
    return object.pose.transform_point(object.mesh.vertices[static_cast<std::size_t>(v)]);
  };
  switch (pair.kind) {
    case ContactFeatureKind::kToolVertexSceneFace: {
      const auto& t = object.mesh.triangles[static_cast<std::size_t>(pair.scene_feature)];
      return {world(t[0]), world(t[1]), world(t[2])};
    }
    case ContactFeatureKind::kSceneVertexToolFace:
      return {world(pair.scene_feature)};
    case ContactFeatureKind::kEdgeEdge: {
      const auto& e =
          ccd.scene_edges(pair.scene_object)[static_cast<std::size_t>(pair.scene_feature)];
      return {world(e[0]), world(e[1])};
    }
  }
  return {};
}

}  // namespace

TEST_CASE("scene features share a place exactly where their vertices coincide, in order") {
  const std::vector<SceneObject> scene = tiles(3, 0.0);
  const Tool tool = test::meshed_box_tool(Vec3::Constant(0.02));
  const MeshCcd ccd(tool.mesh, scene);
  REQUIRE(ccd.scene_features_share_places());
  // Every scene feature of every kind, as pairs with tool feature 0.
  std::vector<ContactFeatures> pairs;
  for (int o = 0; o < static_cast<int>(scene.size()); ++o) {
    const auto& mesh = scene[static_cast<std::size_t>(o)].mesh;
    for (int t = 0; t < static_cast<int>(mesh.triangles.size()); ++t)
      pairs.push_back({ContactFeatureKind::kToolVertexSceneFace, o, 0, t});
    for (int v = 0; v < static_cast<int>(mesh.vertices.size()); ++v)
      pairs.push_back({ContactFeatureKind::kSceneVertexToolFace, o, 0, v});
    for (int e = 0; e < static_cast<int>(ccd.scene_edges(o).size()); ++e)
      pairs.push_back({ContactFeatureKind::kEdgeEdge, o, 0, e});
  }
  std::vector<int> places;
  ccd.scene_feature_places(pairs, places);
  REQUIRE(places.size() == pairs.size());
  int shared_vertices = 0;
  for (std::size_t a = 0; a < pairs.size(); ++a) {
    const std::vector<Vec3> va = scene_feature_vertices(scene, ccd, pairs[a]);
    bool alone = true;
    for (std::size_t b = 0; b < pairs.size(); ++b) {
      if (a == b || pairs[a].kind != pairs[b].kind) continue;
      const bool coincide = va == scene_feature_vertices(scene, ccd, pairs[b]);
      alone = alone && !coincide;
      if (places[a] >= 0) CHECK((places[a] == places[b]) == coincide);
    }
    CHECK((places[a] < 0) == alone);
    shared_vertices += pairs[a].kind == ContactFeatureKind::kSceneVertexToolFace && !alone;
  }
  // The 16 grid corners on top and the 16 below: the 4 inner ones of each
  // shared by four tiles, the 8 on the sides by two.
  CHECK(shared_vertices == 2 * (4 * 4 + 8 * 2));

  SECTION("tiles apart share nothing") {
    const std::vector<SceneObject> apart = tiles(3, 2e-4);
    const MeshCcd separate(tool.mesh, apart);
    CHECK_FALSE(separate.scene_features_share_places());
    separate.scene_feature_places(pairs, places);
    CHECK(std::all_of(places.begin(), places.end(), [](int p) { return p < 0; }));
  }
}

}  // namespace hb
