// Scene features at one place: separate scene objects that touch (tiles
// laid edge to edge, parts of an assembly) repeat each other's vertices,
// and so their triangles and edges there, exactly. A feature's place is a
// number shared by exactly the features of its kind whose vertices have
// the same coordinates, bit for bit, in the same order: pairs of one kind
// and one tool feature whose scene features share a place have the same
// closest points at every tool pose (mesh_proximity.h reads nothing else of
// the scene feature), so a caller measures one of them for all.
#pragma once

#include <span>
#include <vector>

#include "algorithms/ccd/mesh_ccd.h"
#include "algorithms/ccd/mesh_features.h"

namespace hb::ccd_detail {

class FeaturePlaces {
 public:
  FeaturePlaces() = default;
  /// The places of the features of every scene object.
  explicit FeaturePlaces(std::span<const MeshFeatures> scene);

  /// Whether two scene features of one kind share a place; when not, every
  /// feature is its own and place() is not to be asked.
  bool any_shared() const { return any_shared_; }
  /// The place of the scene feature of `pair` (a triangle, a vertex or an
  /// edge by its kind; indices in range): the least index, over all
  /// objects in order, of the features of that kind at the same place; −1
  /// for a feature alone at its place.
  int place(const ContactFeatures& pair) const {
    const auto object = static_cast<std::size_t>(pair.scene_object);
    const auto kind = static_cast<std::size_t>(pair.kind);
    return place_[kind][static_cast<std::size_t>(begin_[kind][object] + pair.scene_feature)];
  }

 private:
  bool any_shared_ = false;
  // Per object, the index of its first vertex, triangle and edge in the
  // numbering over all objects; per feature in that numbering, its place.
  // Both indexed by ContactFeatureKind: the scene feature of a tool
  // vertex–scene face pair is a triangle, of a scene vertex–tool face pair
  // a vertex, of an edge–edge pair an edge.
  std::vector<int> begin_[3];
  std::vector<int> place_[3];
};

}  // namespace hb::ccd_detail
