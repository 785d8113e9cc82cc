// The outputs of a comparison: the table on stdout, and in the --out
// folder compare.json (every row and the overall verdict), compare.md (for
// a pull-request comment) and junit.xml (one test case per check row).
#pragma once

#include <nlohmann/json.hpp>
#include <ostream>
#include <string>

#include "harness/compare/comparison.h"

namespace hb {

/// Columns scenario, label, check, baseline, candidate, change, verdict,
/// note (failing verdicts in capitals), then a line with the overall verdict.
void print_comparison_table(std::ostream& out, const Comparison& comparison);

/// compare.json: paths, options, overall verdict, counts per verdict, rows.
nlohmann::json comparison_json(const Comparison& comparison);

/// compare.md: a headline verdict line, a table of the failing rows only,
/// and every row inside a collapsed <details> block.
std::string comparison_markdown(const Comparison& comparison);

/// junit.xml: one test case per row (class "<scenario>.<label>", name the
/// check); regressions and failures are failures, n/a rows are skipped.
std::string comparison_junit_xml(const Comparison& comparison);

}  // namespace hb
