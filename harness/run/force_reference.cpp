#include "harness/run/force_reference.h"

#include <chrono>
#include <cstring>
#include <functional>
#include <stdexcept>

#include "hapticbench/cache_directory.h"
#include "hapticbench/content_hash.h"
#include "hapticbench/disk_cache.h"
#include "harness/process/interrupt.h"
#include "harness/reference/coupling_damper.h"
#include "harness/reference/rigid_proxy_reference.h"

namespace hb {

namespace {

// Bump when the reference's results change for the same inputs.
// 3: the coupling's damper in the display; 4: the friction's moment.
// 5: the tool's sharp edges; 6: friction as one Coulomb cone per contact;
// 7: sweeps stopped at a clear stick, near triangles in one order.
constexpr int kReferenceVersion = 7;

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
  add_double(scenario.context.coupling.b_t);
  add_double(scenario.context.coupling.b_r);
  add_double(settings.sample_spacing_m);
  add_double(settings.clearance_m);
  hash.add(std::to_string(scenario.reference.force_every)).add(";");
  scenario.trajectory.for_each([&](const DeviceSample& sample) {
    hash.add(
        std::string_view(reinterpret_cast<const char*>(sample.pose.p.data()), 3 * sizeof(double)));
    hash.add(std::string_view(reinterpret_cast<const char*>(sample.pose.q.coeffs().data()),
                              4 * sizeof(double)));
    // The damper reads the device's velocity.
    hash.add(
        std::string_view(reinterpret_cast<const char*>(sample.twist.v.data()), 3 * sizeof(double)));
    hash.add(
        std::string_view(reinterpret_cast<const char*>(sample.twist.w.data()), 3 * sizeof(double)));
  });
  return hash.hex();
}

// The cached bytes: the description's counts, then one ForceReferenceRecord
// per tick.
std::string description_bytes(const ForceReferenceTrack& track) {
  const ForceReferenceDescription& d = track.description;
  std::string bytes;
  const auto put = [&](const auto& value) {
    bytes.append(reinterpret_cast<const char*>(&value), sizeof value);
  };
  put(static_cast<int64_t>(track.ticks.size()));
  put(d.evaluated_ticks), put(d.not_started_ticks), put(d.unconverged_ticks),
      put(d.infeasible_ticks), put(d.max_iterations), put(d.kkt_residual_max), put(d.tool_points),
      put(d.sticking_ticks);
  return bytes;
}

// Hands the cached bytes to `put` in parts of at most a block of records.
void serialise(const ForceReferenceTrack& track, const std::function<void(std::string_view)>& put) {
  put(description_bytes(track));
  SpillBuffer<ForceReferenceRecord>::Reader reader(track.ticks);
  std::vector<ForceReferenceRecord> part;
  part.reserve(SpillBuffer<ForceReferenceRecord>::kBlockItems);
  const auto flush = [&] {
    put(std::string_view(reinterpret_cast<const char*>(part.data()),
                         part.size() * sizeof(ForceReferenceRecord)));
    part.clear();
  };
  for (ForceReferenceRecord record; reader.next(record);) {
    part.push_back(record);
    if (part.size() == part.capacity()) flush();
  }
  if (!part.empty()) flush();
}

uint64_t serialised_bytes(const ForceReferenceTrack& track) {
  return description_bytes(track).size() + track.ticks.size() * sizeof(ForceReferenceRecord);
}

// Reads the cache file's parts into `track`: false when they do not hold
// `ticks` records (a foreign or cut file) or the file is not used.
bool deserialise(const DiskCache& cache, const std::string& key, int64_t ticks,
                 ForceReferenceTrack& track) {
  ForceReferenceDescription& d = track.description;
  const std::size_t header_bytes = description_bytes(track).size();
  std::string pending;  // bytes not yet a whole header or record
  bool header_read = false, fits = true;
  int64_t records = 0;
  const bool hit = cache.read_parts(key, [&](std::string_view part) {
    if (!fits) return;
    pending.append(part);
    std::size_t at = 0;
    const auto get = [&](auto& value) {
      std::memcpy(&value, pending.data() + at, sizeof value);
      at += sizeof value;
    };
    if (!header_read) {
      if (pending.size() < header_bytes) return;
      int64_t count = 0;
      get(count);
      get(d.evaluated_ticks), get(d.not_started_ticks), get(d.unconverged_ticks),
          get(d.infeasible_ticks), get(d.max_iterations), get(d.kkt_residual_max),
          get(d.tool_points), get(d.sticking_ticks);
      header_read = true;
      fits = count == ticks;
    }
    for (; fits && pending.size() - at >= sizeof(ForceReferenceRecord); ++records) {
      if (records == ticks) {
        fits = false;
        break;
      }
      ForceReferenceRecord record;
      get(record);
      track.ticks.push_back(record);
    }
    pending.erase(0, at);
  });
  return hit && fits && header_read && records == ticks && pending.empty();
}

}  // namespace

bool wants_mesh_force_reference(const Scenario& scenario, bool analytic_covered) {
  return scenario.reference.force == "auto" && !analytic_covered && !scenario.context.scene.empty();
}

namespace {

RigidProxySettings reference_settings(const Scenario& scenario) {
  RigidProxySettings settings;
  settings.sample_spacing_m = scenario.reference.sample_spacing_m;
  return settings;
}

// What the reference is, and its settings; the counts come from following.
ForceReferenceDescription base_description(const Scenario& scenario, const std::string& path) {
  const RigidProxySettings settings = reference_settings(scenario);
  ForceReferenceDescription d;
  d.method =
      "rigid proxy: coupling energy minimised over non-penetrating poses reached continuously "
      "(Embree geometry), the scene's Coulomb friction on its translation with its moment, the "
      "coupling's "
      "damper on the proxy's path; along " +
      path;
  d.every = scenario.reference.force_every;
  d.clearance_m = settings.clearance_m;
  for (const SceneObject& object : scenario.context.scene)
    d.friction = d.friction || (settings.friction && object.friction > 0);
  return d;
}

}  // namespace

ForceReferenceFollower::ForceReferenceFollower(const Scenario& scenario, std::string path)
    : reference_(scenario.context.scene, scenario.context.tool.mesh, scenario.context.coupling,
                 reference_settings(scenario)),
      damper_(scenario.context.coupling, scenario.context.dt_s),
      description_(base_description(scenario, path)) {
  description_.tool_points = static_cast<int64_t>(reference_.sample_count());
}

std::optional<IdealRendering> ForceReferenceFollower::follow(const DeviceSample& sample) {
  if (sample.tick % description_.every != 0 || !is_finite(sample.pose)) return std::nullopt;
  const auto t0 = std::chrono::steady_clock::now();
  std::optional<IdealRendering> ideal = reference_.update(sample.pose);
  if (ideal) {
    damper_.apply(sample.tick, sample.twist, *ideal);
    const RigidProxyUpdateStats& stats = reference_.last_stats();
    ForceReferenceDescription& out = description_;
    ++out.evaluated_ticks;
    out.max_iterations = std::max(out.max_iterations, stats.iterations);
    if (!stats.converged) ++out.unconverged_ticks;
    if (stats.infeasible) ++out.infeasible_ticks;
    if (stats.sticking) ++out.sticking_ticks;
    if (stats.converged) out.kkt_residual_max = std::max(out.kkt_residual_max, stats.kkt_residual);
  } else {
    ++description_.not_started_ticks;
  }
  description_.seconds +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return ideal;
}

ForceReferenceTrack compute_force_reference(const Scenario& scenario, ProgressDisplay* progress) {
  const RigidProxySettings settings = reference_settings(scenario);
  const int64_t ticks = scenario.trajectory.ticks();
  const DiskCache cache(default_cache_directory(), "force_reference");
  const std::string key = cache_key(scenario, settings);
  constexpr const char* kAlongTrace = "the trace";
  ForceReferenceTrack track;
  track.description = base_description(scenario, kAlongTrace);
  if (deserialise(cache, key, ticks, track)) {
    track.description.cache_hit = true;
    return track;
  }
  track = ForceReferenceTrack{};

  // The follower builds the reference's geometry: made only on a miss.
  ForceReferenceFollower follower(scenario, kAlongTrace);
  if (progress) {
    progress->task(scenario.name + " / force reference");
    progress->phase("force reference", ticks);
  }
  scenario.trajectory.for_each([&](const DeviceSample& sample) {
    const int64_t tick = sample.tick;
    if (progress) progress->advance(tick + 1);
    if (tick % 64 == 0) throw_if_interrupted();  // a stop request ends the phase here
    // One record per tick of the trajectory, in order.
    while (static_cast<int64_t>(track.ticks.size()) < tick) track.ticks.push_back({});
    ForceReferenceRecord record;
    if (const std::optional<IdealRendering> ideal = follower.follow(sample)) {
      record.evaluated = 1;
      record.in_contact = ideal->in_contact ? 1 : 0;
      for (int k = 0; k < 3; ++k) {
        record.display[k] = ideal->display.force[k];
        record.display[3 + k] = ideal->display.torque[k];
      }
    }
    track.ticks.push_back(record);
  });
  while (static_cast<int64_t>(track.ticks.size()) < ticks) track.ticks.push_back({});
  if (progress) progress->finish_task();
  track.description = follower.description();
  cache.write_parts(
      key, serialised_bytes(track),
      [&](const std::function<void(std::string_view)>& put) { serialise(track, put); });
  return track;
}

const ForceReferenceTick& ForceReferenceTrack::Reader::at(int64_t tick) {
  if (tick < next_ - 1 || tick < 0)
    throw std::logic_error("force reference read out of order: tick " + std::to_string(tick));
  ForceReferenceRecord record;
  while (next_ <= tick) {
    if (!records_.next(record))
      throw std::logic_error("force reference has no tick " + std::to_string(tick));
    ++next_;
    if (next_ == tick + 1) {
      current_.evaluated = record.evaluated != 0;
      current_.in_contact = record.in_contact != 0;
      for (int k = 0; k < 3; ++k) {
        current_.display.force[k] = record.display[k];
        current_.display.torque[k] = record.display[3 + k];
      }
    }
  }
  return current_;
}

}  // namespace hb
