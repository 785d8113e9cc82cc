#include "harness/run/force_reference.h"

#include <chrono>
#include <cstring>

#include "hapticbench/cache_directory.h"
#include "hapticbench/content_hash.h"
#include "hapticbench/disk_cache.h"
#include "harness/reference/rigid_proxy_reference.h"

namespace hb {

namespace {

// Bump when the reference's results change for the same inputs.
constexpr int kReferenceVersion = 2;

std::string cache_key(const Scenario& scenario, const RigidProxySettings& settings) {
  ContentHash hash;
  const auto add_double = [&](double value) { hash.add(exact_key_text(value)).add(","); };
  hash.add("rigid_proxy_reference v").add(std::to_string(kReferenceVersion)).add(";");
  for (const SceneObject& object : scenario.context.scene) {
    hash.add(mesh_geometry_hash(object.mesh)).add(exact_key_text(object.pose));
    hash.add(object.distance_only ? "d;" : "c;");
    add_double(object.friction);
  }
  hash.add(mesh_geometry_hash(scenario.context.tool.mesh));
  add_double(scenario.context.coupling.k_t);
  add_double(scenario.context.coupling.k_r);
  add_double(settings.sample_spacing_m);
  add_double(settings.clearance_m);
  hash.add(std::to_string(scenario.reference.force_every)).add(";");
  scenario.trajectory.for_each([&](const DeviceSample& sample) {
    hash.add(
        std::string_view(reinterpret_cast<const char*>(sample.pose.p.data()), 3 * sizeof(double)));
    hash.add(std::string_view(reinterpret_cast<const char*>(sample.pose.q.coeffs().data()),
                              4 * sizeof(double)));
  });
  return hash.hex();
}

// The cached bytes: the description's counts, then one record per tick.
struct TickRecord {
  uint8_t evaluated, in_contact;
  double display[6];
};

std::string serialise(const ForceReferenceTrack& track) {
  const ForceReferenceDescription& d = track.description;
  std::string bytes;
  const auto put = [&](const auto& value) {
    bytes.append(reinterpret_cast<const char*>(&value), sizeof value);
  };
  put(static_cast<int64_t>(track.ticks.size()));
  put(d.evaluated_ticks), put(d.not_started_ticks), put(d.unconverged_ticks),
      put(d.infeasible_ticks), put(d.max_iterations), put(d.kkt_residual_max), put(d.tool_points),
      put(d.sticking_ticks);
  for (const ForceReferenceTick& tick : track.ticks) {
    TickRecord record{tick.evaluated, tick.in_contact, {}};
    for (int k = 0; k < 3; ++k) {
      record.display[k] = tick.display.force[k];
      record.display[3 + k] = tick.display.torque[k];
    }
    put(record);
  }
  return bytes;
}

// False when the bytes do not hold `ticks` records (a foreign or cut file).
bool deserialise(std::string_view bytes, int64_t ticks, ForceReferenceTrack& track) {
  std::size_t at = 0;
  const auto get = [&](auto& value) {
    if (bytes.size() - at < sizeof value) return false;
    std::memcpy(&value, bytes.data() + at, sizeof value);
    at += sizeof value;
    return true;
  };
  ForceReferenceDescription& d = track.description;
  int64_t count = 0;
  if (!get(count) || count != ticks) return false;
  if (!(get(d.evaluated_ticks) && get(d.not_started_ticks) && get(d.unconverged_ticks) &&
        get(d.infeasible_ticks) && get(d.max_iterations) && get(d.kkt_residual_max) &&
        get(d.tool_points) && get(d.sticking_ticks)))
    return false;
  if (bytes.size() - at != static_cast<std::size_t>(ticks) * sizeof(TickRecord)) return false;
  track.ticks.resize(static_cast<std::size_t>(ticks));
  for (ForceReferenceTick& tick : track.ticks) {
    TickRecord record{};
    get(record);
    tick.evaluated = record.evaluated != 0;
    tick.in_contact = record.in_contact != 0;
    for (int k = 0; k < 3; ++k) {
      tick.display.force[k] = record.display[k];
      tick.display.torque[k] = record.display[3 + k];
    }
  }
  return true;
}

}  // namespace

bool wants_mesh_force_reference(const Scenario& scenario, bool analytic_covered) {
  return scenario.reference.force == "auto" && !analytic_covered && !scenario.context.scene.empty();
}

ForceReferenceTrack compute_force_reference(const Scenario& scenario, ProgressDisplay* progress) {
  RigidProxySettings settings;
  settings.sample_spacing_m = scenario.reference.sample_spacing_m;
  ForceReferenceDescription d;
  d.method =
      "rigid proxy: coupling energy minimised over non-penetrating poses reached continuously "
      "(Embree geometry), the scene's Coulomb friction on its translation";
  d.every = scenario.reference.force_every;
  d.clearance_m = settings.clearance_m;
  for (const SceneObject& object : scenario.context.scene)
    d.friction = d.friction || (settings.friction && object.friction > 0);
  const int64_t ticks = scenario.trajectory.ticks();

  const DiskCache cache(default_cache_directory(), "force_reference");
  const std::string key = cache_key(scenario, settings);
  ForceReferenceTrack track;
  track.description = d;
  if (const DiskCache::Lookup lookup = cache.read(key);
      lookup.payload && deserialise(*lookup.payload, ticks, track)) {
    track.description.cache_hit = true;
    return track;
  }
  track = ForceReferenceTrack{};
  track.description = d;
  ForceReferenceDescription& out = track.description;

  const auto t0 = std::chrono::steady_clock::now();
  RigidProxyReference reference(scenario.context.scene, scenario.context.tool.mesh,
                                scenario.context.coupling, settings);
  out.tool_points = static_cast<int64_t>(reference.sample_count());
  track.ticks.resize(static_cast<std::size_t>(ticks));
  if (progress) {
    progress->task(scenario.name + " / force reference");
    progress->phase("force reference", ticks);
  }
  scenario.trajectory.for_each([&](const DeviceSample& sample) {
    const int64_t tick = sample.tick;
    if (progress) progress->advance(tick + 1);
    if (tick % out.every != 0 || !is_finite(sample.pose)) return;
    const std::optional<IdealRendering> ideal = reference.update(sample.pose);
    if (!ideal) {
      ++out.not_started_ticks;
      return;
    }
    const RigidProxyUpdateStats& stats = reference.last_stats();
    ++out.evaluated_ticks;
    out.max_iterations = std::max(out.max_iterations, stats.iterations);
    if (!stats.converged) ++out.unconverged_ticks;
    if (stats.infeasible) ++out.infeasible_ticks;
    if (stats.sticking) ++out.sticking_ticks;
    if (stats.converged) out.kkt_residual_max = std::max(out.kkt_residual_max, stats.kkt_residual);
    ForceReferenceTick& record = track.ticks[static_cast<std::size_t>(tick)];
    record.evaluated = true;
    record.in_contact = ideal->in_contact;
    record.display = ideal->display;
  });
  if (progress) progress->finish_task();
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  cache.write(key, serialise(track));
  return track;
}

}  // namespace hb
