#include "algorithms/ccd/feature_places.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <numeric>

namespace hb::ccd_detail {
namespace {

// Sorts the indices 0 … n − 1 by key(i) (ties by index) and gives each the
// least index of its run of equal keys, or −1 when it is alone in its run;
// returns whether any run is longer than one.
template <class Key>
bool places_by_key(std::size_t n, Key&& key, std::vector<int>& place) {
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const auto ka = key(a), kb = key(b);
    return ka < kb || (ka == kb && a < b);
  });
  place.assign(n, -1);
  bool shared = false;
  for (std::size_t run = 0, end = 0; run < n; run = end) {
    for (end = run + 1; end < n && key(order[end]) == key(order[run]);) ++end;
    if (end - run == 1) continue;
    shared = true;
    for (std::size_t i = run; i < end; ++i) place[static_cast<std::size_t>(order[i])] = order[run];
  }
  return shared;
}

std::array<uint64_t, 3> bits_of(const Vec3& v) {
  return {std::bit_cast<uint64_t>(v.x()), std::bit_cast<uint64_t>(v.y()),
          std::bit_cast<uint64_t>(v.z())};
}

}  // namespace

FeaturePlaces::FeaturePlaces(std::span<const MeshFeatures> scene) {
  constexpr auto kTriangle = static_cast<std::size_t>(ContactFeatureKind::kToolVertexSceneFace);
  constexpr auto kVertex = static_cast<std::size_t>(ContactFeatureKind::kSceneVertexToolFace);
  constexpr auto kEdge = static_cast<std::size_t>(ContactFeatureKind::kEdgeEdge);
  std::vector<const Vec3*> vertices;
  for (const MeshFeatures& object : scene) {
    begin_[kVertex].push_back(static_cast<int>(vertices.size()));
    for (const Vec3& v : object.vertices) vertices.push_back(&v);
  }
  // Triangles and edges can share a place only where vertices do.
  std::vector<int>& vertex_place = place_[kVertex];
  if (!places_by_key(
          vertices.size(), [&](int v) { return bits_of(*vertices[static_cast<std::size_t>(v)]); },
          vertex_place)) {
    *this = FeaturePlaces();
    return;
  }
  std::vector<std::array<int, 3>> triangles;
  std::vector<std::array<int, 2>> edges;
  for (std::size_t o = 0; o < scene.size(); ++o) {
    const int first = begin_[kVertex][o];
    // A vertex alone at its place is its own (its index over all objects).
    const auto placed = [&](int v) {
      const int place = vertex_place[static_cast<std::size_t>(first + v)];
      return place >= 0 ? place : first + v;
    };
    begin_[kTriangle].push_back(static_cast<int>(triangles.size()));
    for (const std::array<int, 3>& t : scene[o].triangles)
      triangles.push_back({placed(t[0]), placed(t[1]), placed(t[2])});
    begin_[kEdge].push_back(static_cast<int>(edges.size()));
    for (const std::array<int, 2>& e : scene[o].edges)
      edges.push_back({placed(e[0]), placed(e[1])});
  }
  places_by_key(
      triangles.size(), [&](int t) { return triangles[static_cast<std::size_t>(t)]; },
      place_[kTriangle]);
  places_by_key(
      edges.size(), [&](int e) { return edges[static_cast<std::size_t>(e)]; }, place_[kEdge]);
  any_shared_ = true;
}

}  // namespace hb::ccd_detail
