#include "algorithms/registry.h"

#include "algorithms/constrained_dynamics/constrained_dynamics.h"
#include "algorithms/core/input_error.h"
#include "algorithms/coupling_only/coupling_only.h"
#include "algorithms/god_object/god_object.h"
#include "algorithms/penalty_analytic/penalty_analytic.h"
#include "algorithms/sensation_preserving/sensation_preserving.h"
#include "algorithms/voxmap_pointshell/voxmap_pointshell.h"

namespace hb {

namespace {
// Read it like a collision table: one row per algorithm.
constexpr AlgorithmEntry kAlgorithms[] = {
    {"coupling_only", "baseline: dynamic proxy on the virtual coupling, no contacts (transparency)",
     &create_coupling_only},
    {"penalty_analytic",
     "baseline: penalty contact against exact primitive shapes, explicit or implicit Euler",
     &create_penalty_analytic},
    {"god_object",
     "Ortega, Redon & Coquillart 2007: massless proxy, Gauss' least constraint, screw-motion "
     "mesh CCD on the slow loop",
     &create_god_object, true},
    {"god_object_3dof",
     "the god-object's 3-DOF special case: a point tool, segment-triangle CCD, force only",
     &create_god_object_3dof, true},
    {"constrained_dynamics",
     "Duriez et al. 2006: rigid proxy with mass, hard contacts and Coulomb friction as impulses "
     "(projected Gauss-Seidel), implicit coupling, contacts from the shared proximity "
     "certificates",
     &create_constrained_dynamics, true},
    {"voxmap_pointshell",
     "McNeely, Puterbaugh & Troy 1999: scene voxmap (OpenVDB), tool pointshell, tangent-plane "
     "penalty per point, dynamic proxy",
     &create_voxmap_pointshell},
    {"sensation_preserving",
     "Otaduy & Lin 2003/2005: convex hierarchies refined where detail is perceptible, GJK/EPA, "
     "k-means contact clusters, penalty proxy with implicit Euler",
     &create_sensation_preserving},
};
}  // namespace

std::span<const AlgorithmEntry> algorithm_table() { return kAlgorithms; }

const AlgorithmEntry* find_algorithm(std::string_view name) {
  for (const AlgorithmEntry& entry : kAlgorithms)
    if (entry.name == name) return &entry;
  return nullptr;
}

std::unique_ptr<Renderer> create_renderer(const std::string& name, const RenderContext& context,
                                          const ParamSet& params, const std::string& field) {
  if (const AlgorithmEntry* entry = find_algorithm(name)) {
    std::unique_ptr<Renderer> renderer = entry->create(context, params);
    params.reject_unknown();
    return renderer;
  }
  std::string known;
  for (const AlgorithmEntry& entry : kAlgorithms)
    known += (known.empty() ? "" : ", ") + std::string(entry.name);
  throw InputError("", field, "unknown algorithm \"" + name + "\" (known: " + known + ")");
}

}  // namespace hb
