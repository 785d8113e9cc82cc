#include "harness/output/ticks_csv.h"

#include <catch2/catch.hpp>
#include <sstream>

namespace hb {
namespace {

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream in(line);
  std::string field;
  while (std::getline(in, field, ',')) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.push_back("");
  return fields;
}

TEST_CASE("the header starts with the contract columns") {
  const std::string contract =
      "tick,t_ns,dev_px,dev_py,dev_pz,dev_qw,dev_qx,dev_qy,dev_qz,proxy_px,proxy_py,proxy_pz,"
      "proxy_qw,proxy_qx,proxy_qy,proxy_qz,fx,fy,fz,tx,ty,tz,contacts,penetration_m,step_ns,"
      "flags";
  CHECK(ticks_csv_header().rfind(contract, 0) == 0);
}

TEST_CASE("rows carry exact numbers and the hash ignores wall-clock timings") {
  DeviceSample device;
  device.tick = 7;
  device.t_ns = 7'000'000;
  device.pose.p = Vec3(0.1, 1.0 / 3.0, -2e-9);
  TickRecord record;
  record.device = &device;
  record.result.display.force = Vec3(1.0 / 7.0, 0, -3);
  record.result.proxy = device.pose;
  record.step_ns = 1234;
  TickEvaluation evaluation;
  evaluation.penetration_m = 0.001;

  std::ostringstream a_text, b_text, c_text;
  TicksCsvWriter a(a_text), b(b_text), c(c_text);
  a.add(record, evaluation);
  record.step_ns = 98765;  // only the timing differs
  b.add(record, evaluation);
  record.result.display.force.x() = std::nextafter(1.0 / 7.0, 1.0);  // one ulp
  c.add(record, evaluation);

  CHECK(a.deterministic_hash() == b.deterministic_hash());
  CHECK(a.deterministic_hash() != c.deterministic_hash());
  REQUIRE(a.finish());
  REQUIRE(b.finish());
  CHECK(a_text.str() != b_text.str());

  std::stringstream in(a_text.str());
  std::string header, row;
  std::getline(in, header);
  std::getline(in, row);
  const auto names = split(header);
  const auto fields = split(row);
  REQUIRE(names.size() == fields.size());
  auto column = [&](const std::string& name) {
    for (std::size_t i = 0; i < names.size(); ++i)
      if (names[i] == name) return fields[i];
    FAIL("no column " << name);
    return std::string();
  };
  CHECK(std::stod(column("dev_py")) == 1.0 / 3.0);
  CHECK(std::stod(column("fx")) == 1.0 / 7.0);
  CHECK(column("step_ns") == "1234");
  CHECK(column("tick") == "7");
  CHECK(std::stod(column("penetration_m")) == 0.001);
  CHECK(column("ref_fx").empty());  // no analytic reference: empty, not zero
}

}  // namespace
}  // namespace hb
