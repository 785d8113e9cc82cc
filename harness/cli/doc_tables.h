// The tables the docs repeat from the code, as Markdown, printed by
// `hapticbench list` so that the docs can be checked against them
// (tests/end_to_end/docs_tables_test.cpp, metric_table_doc_test.cpp).
#pragma once

#include <ostream>

namespace hb {

/// Every metric: its place in summary.json, unit, budget and comparison
/// (docs/metric-table.md; list --metrics).
void print_metric_table(std::ostream& out);

/// Every generator's parameters as its code asks for them: each generator
/// runs once, for a 1 s trace, with no parameters given (traces/README.md;
/// list --generators).
void print_generator_parameters(std::ostream& out);

/// Every algorithm's parameters as its code asks for them: each algorithm
/// is built once on a probe scene with no parameters given; a parameter
/// read only under another parameter's non-default value is not listed
/// (docs/algorithms/README.md; list --params).
void print_algorithm_parameters(std::ostream& out);

/// The plausible ranges of scenario fields and trace files (docs/limits.md;
/// list --limits).
void print_plausible_ranges(std::ostream& out);

}  // namespace hb
