#include "algorithms/registry.h"

#include <iterator>
#include <vector>

#include "algorithms/constrained_dynamics/constrained_dynamics.h"
#include "algorithms/coupling_only/coupling_only.h"
#include "algorithms/god_object/god_object.h"
#include "algorithms/penalty_analytic/penalty_analytic.h"
#include "algorithms/sensation_preserving/sensation_preserving.h"
#include "algorithms/voxmap_pointshell/voxmap_pointshell.h"
#include "hapticbench/input_error.h"

namespace hb {

namespace {
// Read it like a collision table: one row per algorithm.
constexpr AlgorithmEntry kAlgorithms[] = {
    {.name = "coupling_only",
     .summary = "baseline: dynamic proxy on the virtual coupling, no contacts (transparency)",
     .create = &create_coupling_only},
    {.name = "penalty_analytic",
     .summary =
         "baseline: penalty contact against exact primitive shapes, explicit or implicit Euler",
     .create = &create_penalty_analytic},
    {.name = "god_object",
     .summary = "Ortega, Redon & Coquillart 2007: massless proxy, Gauss' least constraint, "
                "screw-motion mesh CCD on the slow loop",
     .create = &create_god_object,
     .renders_friction = true},
    {.name = "god_object_3dof",
     .summary =
         "the god-object's 3-DOF special case: a point tool, segment-triangle CCD, force only",
     .create = &create_god_object_3dof,
     .renders_friction = true},
    {.name = "constrained_dynamics",
     .summary = "Duriez et al. 2006: rigid proxy with mass, hard contacts and Coulomb friction as "
                "impulses (projected Gauss-Seidel), implicit coupling, contacts from the shared "
                "proximity certificates",
     .create = &create_constrained_dynamics,
     .renders_friction = true},
    {.name = "voxmap_pointshell",
     .summary = "McNeely, Puterbaugh & Troy 1999: scene voxmap (OpenVDB), tool pointshell, "
                "tangent-plane penalty per point, dynamic proxy",
     .create = &create_voxmap_pointshell},
    {.name = "sensation_preserving",
     .summary = "Otaduy & Lin 2003/2005: convex hierarchies refined where detail is perceptible, "
                "GJK/EPA, k-means contact clusters, penalty proxy with implicit Euler",
     .create = &create_sensation_preserving},
};

// The table as the process sees it: the built-in rows, then registered ones
// with their origins. Plugins register before any run starts.
struct Table {
  std::vector<AlgorithmEntry> rows{std::begin(kAlgorithms), std::end(kAlgorithms)};
  std::vector<std::string> origins = std::vector<std::string>(std::size(kAlgorithms));
};

Table& table() {
  static Table instance;
  return instance;
}
}  // namespace

std::span<const AlgorithmEntry> algorithm_table() { return table().rows; }

const AlgorithmEntry* find_algorithm(std::string_view name) {
  for (const AlgorithmEntry& entry : table().rows)
    if (entry.name == name) return &entry;
  return nullptr;
}

std::string algorithm_origin(std::string_view name) {
  const Table& t = table();
  for (std::size_t i = 0; i < t.rows.size(); ++i)
    if (t.rows[i].name == name) return t.origins[i];
  return "";
}

void register_algorithms(std::span<const AlgorithmEntry> rows, const std::string& origin) {
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const AlgorithmEntry& row = rows[i];
    if (row.name.empty() || row.create == nullptr)
      throw InputError(origin, "",
                       "algorithm row " + std::to_string(i) + " has no name or no create function");
    if (find_algorithm(row.name)) {
      const std::string owner = algorithm_origin(row.name);
      throw InputError(origin, "",
                       "the algorithm name \"" + std::string(row.name) + "\" is taken by " +
                           (owner.empty() ? std::string("a built-in algorithm") : owner));
    }
    for (std::size_t j = 0; j < i; ++j)
      if (rows[j].name == row.name)
        throw InputError(origin, "",
                         "the algorithm name \"" + std::string(row.name) + "\" is given twice");
  }
  Table& t = table();
  for (const AlgorithmEntry& row : rows) {
    t.rows.push_back(row);
    t.origins.push_back(origin);
  }
}

std::unique_ptr<Renderer> create_renderer(const std::string& name, const RenderContext& context,
                                          const ParamSet& params, const std::string& field) {
  if (const AlgorithmEntry* entry = find_algorithm(name)) {
    std::unique_ptr<Renderer> renderer = entry->create(context, params);
    params.reject_unknown();
    return renderer;
  }
  throw InputError("", field, unknown_algorithm_message(name));
}

std::string unknown_algorithm_message(std::string_view name) {
  std::string known;
  for (const AlgorithmEntry& entry : table().rows)
    known += (known.empty() ? "" : ", ") + std::string(entry.name);
  return "unknown algorithm \"" + std::string(name) + "\" (known: " + known +
         "; a renderer built outside hapticbench loads with --plugin PATH.so, docs/plugins.md)";
}

}  // namespace hb
