// Test support: scenes and parameters the renderer tests share.
#pragma once

#include <initializer_list>
#include <utility>

#include "hapticbench/param_set.h"
#include "hapticbench/scene.h"
#include "hapticbench/shapes.h"
#include "tests/support/proxy_fixtures.h"

namespace hb::test {

/// A 2 cm sphere tool (an icosphere of `subdivisions`, content hash
/// "sphere") over a 40 × 40 × 2 cm slab (content hash "slab") whose top face
/// is z = top_z; the example coupling gains; no reach box.
inline RenderContext sphere_over_slab(int subdivisions, double top_z = 0) {
  RenderContext context;
  SceneObject slab;
  slab.name = "slab";
  Shape box;
  box.type = ShapeType::kBox;
  box.size = Vec3(0.4, 0.4, 0.02);
  slab.shape = box;
  slab.mesh = shape_mesh(box);
  slab.pose.p = Vec3(0, 0, top_z - 0.01);
  slab.content_hash = "slab";
  context.scene = {slab};
  context.tool = sphere_tool(0.02);
  context.tool.shape->subdivisions = subdivisions;
  context.tool.mesh = shape_mesh(*context.tool.shape);
  context.tool.content_hash = "sphere";
  context.coupling = example_gains();
  return context;
}

/// Algorithm parameters as a scenario's "params" would give them.
inline ParamSet params_of(std::initializer_list<std::pair<const char*, ParamValue>> values) {
  ParamSet params("/algorithms/0/params");
  for (const auto& [key, value] : values) params.set(key, value);
  return params;
}

}  // namespace hb::test
