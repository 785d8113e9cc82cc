// The metric table's rows agree with themselves: unique names and places,
// a value kind that matches how compare checks the metric, a reader and a
// description for every row.
#include "harness/metrics/metric_table.h"

#include <catch2/catch.hpp>
#include <set>
#include <string>

namespace hb {
namespace {

TEST_CASE("every metric row is complete, unique and typed as compare checks it") {
  std::set<std::string_view> names, pointers;
  for (const MetricDefinition& metric : metric_table()) {
    INFO(metric.name);
    CHECK(names.insert(metric.name).second);
    CHECK(pointers.insert(metric.json_pointer).second);
    CHECK(metric.json_pointer.substr(0, 1) == "/");
    CHECK_FALSE(metric.unit.empty());
    CHECK_FALSE(metric.description.empty());
    CHECK(metric.read != nullptr);
    // A flag is compared as a flag, a count as a count.
    if (metric.compare == CompareRule::kFlag) CHECK(metric.kind == ValueKind::kFlag);
    if (metric.compare == CompareRule::kCount) CHECK(metric.kind == ValueKind::kCount);
    if (metric.kind == ValueKind::kFlag) CHECK(metric.unit == "flag");
    CHECK(find_metric(metric.name) == &metric);
  }
  CHECK(find_metric("no_such_metric") == nullptr);
}

TEST_CASE("a flag reads as 0 or 1 and a count as a whole number") {
  RunMetrics m;
  m.stability.diverged = true;
  m.stability.nonfinite = 7;
  CHECK(find_metric("diverged")->read(m) == 1.0);
  CHECK(find_metric("nonfinite")->read(m) == 7.0);
  CHECK(find_metric("nonfinite")->counted_as == "ticks with a non-finite wrench");
  CHECK(find_metric("diverged")->counted_as.empty());  // compare calls it by its name
}

}  // namespace
}  // namespace hb
