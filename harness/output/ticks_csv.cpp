#include "harness/output/ticks_csv.h"

#include <charconv>

namespace hb {

const std::string& ticks_csv_header() {
  static const std::string header = [] {
    std::string text =
        "tick,t_ns,dev_px,dev_py,dev_pz,dev_qw,dev_qx,dev_qy,dev_qz,"
        "proxy_px,proxy_py,proxy_pz,proxy_qw,proxy_qx,proxy_qy,proxy_qz,"
        "fx,fy,fz,tx,ty,tz,contacts,penetration_m,step_ns,flags,"
        "ref_fx,ref_fy,ref_fz,ref_tx,ref_ty,ref_tz,slow_update_ns,slow_data_age_ticks";
    // Per oracle backend: deepest sample and samples inside; then the
    // intersection volume of the backend that computes it.
    auto column = [&text](std::string_view backend, std::string_view quantity) {
      text.append(",").append(backend).append(quantity);
    };
    for (const OracleBackendEntry& entry : oracle_backends()) {
      column(entry.name, "_pen_m");
      column(entry.name, "_inside");
    }
    for (const OracleBackendEntry& entry : oracle_backends())
      if (entry.intersection_volume) column(entry.name, "_volume_m3");
    // Distance-only scenes: the tool's distance to the scene, and 1 when it
    // crosses the scene's surface (0 when not).
    text.append(",oracle_distance_m");
    text.append(",oracle_crossing");
    text.append(",oracle_ns");
    return text;
  }();
  return header;
}

const std::vector<std::string>& ticks_csv_timing_columns() {
  static const std::vector<std::string> columns = {"step_ns", "slow_update_ns", "oracle_ns"};
  return columns;
}

namespace {
// Shortest text that reads back to the same double: exact and compact.
void append_number(std::string& out, double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}
void append_integer(std::string& out, int64_t value) {
  char buffer[24];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}
void append_vec3(std::string& out, const Vec3& v) {
  for (int i = 0; i < 3; ++i) {
    out += ',';
    append_number(out, v[i]);
  }
}
void append_pose(std::string& out, const Pose& pose) {
  append_vec3(out, pose.p);
  for (double c : {pose.q.w(), pose.q.x(), pose.q.y(), pose.q.z()}) {
    out += ',';
    append_number(out, c);
  }
}
}  // namespace

constexpr std::size_t kFlushBytes = std::size_t{1} << 18;

TicksCsvWriter::TicksCsvWriter(std::ostream& out) : out_(out) {
  buffer_ = ticks_csv_header() + "\n";
}

bool TicksCsvWriter::finish() {
  out_.write(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
  buffer_.clear();
  out_.flush();
  return static_cast<bool>(out_);
}

void TicksCsvWriter::add(const TickRecord& record, const TickEvaluation& evaluation) {
  const DeviceSample& device = *record.device;
  const TickResult& result = record.result;
  // Deterministic part first, timings kept apart so the hash can skip them.
  std::string head;
  append_integer(head, device.tick);
  head += ',';
  append_integer(head, device.t_ns);
  append_pose(head, device.pose);
  append_pose(head, result.proxy);
  append_vec3(head, result.display.force);
  append_vec3(head, result.display.torque);
  head += ',';
  append_integer(head, static_cast<int64_t>(result.contacts.size()));
  head += ',';
  if (evaluation.penetration_m) append_number(head, *evaluation.penetration_m);

  std::string tail;
  tail += ',';
  append_integer(tail, result.flags);
  if (evaluation.ideal_display) {
    append_vec3(tail, evaluation.ideal_display->force);
    append_vec3(tail, evaluation.ideal_display->torque);
  } else {
    tail += ",,,,,,";
  }
  std::string slow_age;
  slow_age += ',';
  if (record.slow_data_age_ticks >= 0) append_integer(slow_age, record.slow_data_age_ticks);

  // Oracle columns: empty when not evaluated at this tick.
  std::string oracle;
  std::string oracle_ns = ",";
  const auto entries = oracle_backends();
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const BackendPenetration* backend = nullptr;
    if (evaluation.oracle && i < evaluation.oracle->backends.size() &&
        evaluation.oracle->backends[i])
      backend = &*evaluation.oracle->backends[i];
    oracle += ',';
    if (backend) append_number(oracle, backend->result.max_depth_m);
    oracle += ',';
    if (backend) append_integer(oracle, backend->result.inside);
  }
  for (const OracleBackendEntry& entry : entries) {
    if (!entry.intersection_volume) continue;
    oracle += ',';
    if (evaluation.oracle && evaluation.oracle->intersection_volume_m3)
      append_number(oracle, *evaluation.oracle->intersection_volume_m3);
  }
  oracle += ',';
  if (evaluation.oracle && evaluation.oracle->min_distance_m)
    append_number(oracle, *evaluation.oracle->min_distance_m);
  oracle += ',';
  if (evaluation.oracle && evaluation.oracle->crossing)
    append_integer(oracle, *evaluation.oracle->crossing ? 1 : 0);
  if (evaluation.oracle && !evaluation.oracle->broad_phase_skipped)
    append_integer(oracle_ns, evaluation.oracle->total_ns());

  hash_.add(head).add(tail).add(slow_age).add(oracle).add("\n");

  buffer_ += head;
  buffer_ += ',';
  append_integer(buffer_, record.step_ns);
  buffer_ += tail;
  buffer_ += ',';
  if (record.slow_started) append_integer(buffer_, record.slow_ns);
  buffer_ += slow_age;
  buffer_ += oracle;
  buffer_ += oracle_ns;
  buffer_ += '\n';
  if (buffer_.size() >= kFlushBytes) {
    out_.write(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
    buffer_.clear();
  }
}

}  // namespace hb
