#include "harness/compare/comparison_report.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <map>
#include <sstream>
#include <vector>

#include "harness/output/xml_text.h"

namespace hb {

namespace {

using nlohmann::json;

constexpr std::size_t kColumns = 8;
constexpr std::array<const char*, kColumns> kHeader = {"scenario",  "label",  "check",   "baseline",
                                                       "candidate", "change", "verdict", "note"};

std::string upper(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
  return text;
}

// Failing verdicts in capitals so that they stand out in a long table.
std::string shown_verdict(Verdict verdict) {
  const std::string name = verdict_name(verdict);
  return is_failing(verdict) ? upper(name) : name;
}

std::array<std::string, kColumns> cells(const CheckRow& row) {
  return {row.scenario,
          row.label.empty() ? "-" : row.label,
          row.check,
          display_value(row.baseline),
          display_value(row.candidate),
          row.change.empty() ? "-" : row.change,
          shown_verdict(row.verdict),
          row.note};
}

// Width on a terminal: UTF-8 continuation bytes take no column ("N·m").
std::size_t display_width(const std::string& text) {
  std::size_t width = 0;
  for (unsigned char c : text) width += (c & 0xC0) == 0x80 ? 0 : 1;
  return width;
}

std::string headline(const Comparison& comparison) {
  const std::size_t failing = comparison.failing_rows();
  const std::size_t total = comparison.rows.size();
  if (failing == 0) return "pass: " + std::to_string(total) + " checks, no regression";
  return "REGRESSION: " + std::to_string(failing) + " of " + std::to_string(total) +
         " checks failed";
}

std::map<std::string, int> verdict_counts(const Comparison& comparison) {
  std::map<std::string, int> counts;
  for (const CheckRow& row : comparison.rows) ++counts[verdict_name(row.verdict)];
  return counts;
}

std::string markdown_cell(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '|')
      out += "\\|";
    else if (c == '\n')
      out += ' ';
    else
      out += c;
  }
  return out;
}

std::string markdown_table(const std::vector<const CheckRow*>& rows) {
  std::ostringstream out;
  out << "|";
  for (const char* name : kHeader) out << " " << name << " |";
  out << "\n|";
  for (std::size_t i = 0; i < kColumns; ++i) out << " --- |";
  out << "\n";
  for (const CheckRow* row : rows) {
    const std::array<std::string, kColumns> text = cells(*row);
    out << "|";
    for (std::size_t i = 0; i < kColumns; ++i) {
      const std::string cell = markdown_cell(text[i]);
      // Failing verdicts in bold.
      if (i == 6 && is_failing(row->verdict))
        out << " **" << cell << "** |";
      else
        out << " " << cell << " |";
    }
    out << "\n";
  }
  return out.str();
}

}  // namespace

void print_comparison_table(std::ostream& out, const Comparison& comparison) {
  std::vector<std::array<std::string, kColumns>> table;
  std::array<std::string, kColumns> header;
  for (std::size_t i = 0; i < kColumns; ++i) header[i] = kHeader[i];
  table.push_back(header);
  // Regressions and failures first, then every other row in its order.
  for (const bool failing : {true, false})
    for (const CheckRow& row : comparison.rows)
      if (is_failing(row.verdict) == failing) table.push_back(cells(row));
  std::array<std::size_t, kColumns> widths{};
  for (const auto& line : table)
    for (std::size_t i = 0; i < kColumns; ++i)
      widths[i] = std::max(widths[i], display_width(line[i]));
  for (const auto& line : table) {
    std::string text;
    for (std::size_t i = 0; i < kColumns; ++i) {
      text += line[i];
      if (i + 1 < kColumns) text += std::string(widths[i] - display_width(line[i]) + 2, ' ');
    }
    while (!text.empty() && text.back() == ' ') text.pop_back();
    out << text << "\n";
  }
  out << "verdict: " << headline(comparison) << "\n";
}

json comparison_json(const Comparison& comparison) {
  json rows = json::array();
  for (const CheckRow& row : comparison.rows)
    rows.push_back({{"scenario", row.scenario},
                    {"label", row.label.empty() ? json(nullptr) : json(row.label)},
                    {"check", row.check},
                    {"baseline", row.baseline},
                    {"candidate", row.candidate},
                    {"change", row.change},
                    {"verdict", verdict_name(row.verdict)},
                    {"note", row.note},
                    {"detail", row.detail}});
  const CompareOptions& o = comparison.options;
  return {{"schema_version", 1},
          {"baseline", comparison.baseline_path},
          {"candidate", comparison.candidate_path},
          {"options",
           {{"rel_tol", o.rel_tol},
            {"timing_ratio", o.timing_ratio},
            {"alpha", o.alpha},
            {"timing", o.timing}}},
          {"verdict", comparison.passed() ? "pass" : "regression"},
          {"checks", comparison.rows.size()},
          {"failing", comparison.failing_rows()},
          {"counts", verdict_counts(comparison)},
          {"rows", rows}};
}

std::string comparison_markdown(const Comparison& comparison) {
  std::vector<const CheckRow*> failing, all;
  for (const CheckRow& row : comparison.rows) {
    all.push_back(&row);
    if (is_failing(row.verdict)) failing.push_back(&row);
  }
  std::ostringstream out;
  out << "**hapticbench compare: " << headline(comparison) << "** (baseline `"
      << comparison.baseline_path << "`, candidate `" << comparison.candidate_path << "`)\n\n";
  if (!failing.empty()) out << markdown_table(failing) << "\n";
  out << "<details><summary>All " << all.size() << " checks</summary>\n\n"
      << markdown_table(all) << "\n</details>\n";
  return out.str();
}

std::string comparison_junit_xml(const Comparison& comparison) {
  std::ostringstream cases;
  for (const CheckRow& row : comparison.rows) {
    const std::string classname = row.label.empty() ? row.scenario : row.scenario + "." + row.label;
    cases << "    <testcase classname=\"" << xml_escape(classname) << "\" name=\""
          << xml_escape(row.check) << "\">";
    if (is_failing(row.verdict)) {
      cases << "<failure message=\"" << xml_escape(row.note) << "\" type=\""
            << verdict_name(row.verdict) << "\">"
            << xml_escape("baseline " + display_value(row.baseline) + ", candidate " +
                          display_value(row.candidate) +
                          (row.change.empty() ? "" : ", change " + row.change))
            << "</failure>";
    } else if (row.verdict == Verdict::kNotApplicable) {
      cases << "<skipped message=\"" << xml_escape(row.note) << "\"/>";
    } else {
      // A passing case carries its figures too: what was measured, against what.
      cases << "<system-out>"
            << xml_escape(std::string(verdict_name(row.verdict)) + ": baseline " +
                          display_value(row.baseline) + ", candidate " +
                          display_value(row.candidate) +
                          (row.change.empty() ? "" : ", change " + row.change) +
                          (row.note.empty() ? "" : "; " + row.note))
            << "</system-out>";
    }
    cases << "</testcase>\n";
  }
  const std::size_t tests = comparison.rows.size();
  const std::size_t failures = comparison.failing_rows();
  std::ostringstream out;
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      << "<testsuites tests=\"" << tests << "\" failures=\"" << failures << "\">\n"
      << "  <testsuite name=\"hapticbench compare\" tests=\"" << tests << "\" failures=\""
      << failures << "\">\n"
      << cases.str() << "  </testsuite>\n</testsuites>\n";
  return out.str();
}

}  // namespace hb
