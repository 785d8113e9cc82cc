#include "harness/cli/ccd_query_file.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string_view>

#include "hapticbench/input_error.h"
#include "harness/process/input_file.h"

namespace hb {

namespace {

constexpr const char* kFieldNames[7] = {"xnum", "xden", "ynum", "yden", "znum", "zden", "truth"};

std::string_view trimmed(std::string_view text) {
  while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
  while (!text.empty() && (text.back() == ' ' || text.back() == '\t' || text.back() == '\r'))
    text.remove_suffix(1);
  return text;
}

/// A decimal integer: optional sign, then digits only.
bool is_integer(std::string_view text) {
  if (!text.empty() && (text.front() == '-' || text.front() == '+')) text.remove_prefix(1);
  if (text.empty()) return false;
  for (const char c : text)
    if (c < '0' || c > '9') return false;
  return true;
}

/// The integer's digits without sign and leading zeros ("0" for zero).
std::string canonical_digits(std::string_view text) {
  if (text.front() == '-' || text.front() == '+') text.remove_prefix(1);
  while (text.size() > 1 && text.front() == '0') text.remove_prefix(1);
  return std::string(text);
}

/// The double nearest to a decimal integer (strtod rounds correctly), and
/// whether it is exact: printf writes a double's exact decimal value.
double integer_to_double(std::string_view text, bool& exact) {
  const std::string owned(text);
  const double value = std::strtod(owned.c_str(), nullptr);
  if (!std::isfinite(value)) {
    exact = false;
    return value;
  }
  char printed[400];
  std::snprintf(printed, sizeof printed, "%.0f", std::abs(value));
  exact = canonical_digits(owned) == printed;
  return value;
}

struct Row {
  Vec3 point;
  int truth = 0;
  int line = 0;
};

Row parse_row(const std::string& source, int line_number, std::string_view line,
              int& inexact_coordinates) {
  const std::string where = "line " + std::to_string(line_number);
  std::string_view fields[7];
  int count = 0;
  while (true) {
    const std::size_t comma = line.find(',');
    if (count < 7) fields[count] = trimmed(line.substr(0, comma));
    ++count;
    if (comma == std::string_view::npos) break;
    line.remove_prefix(comma + 1);
  }
  if (count != 7)
    throw InputError(source, where,
                     "expected 7 comma-separated integers xnum,xden,ynum,yden,znum,zden,truth, "
                     "found " +
                         std::to_string(count) + " fields");
  for (int f = 0; f < 7; ++f)
    if (!is_integer(fields[f]))
      throw InputError(source, where,
                       std::string("field ") + kFieldNames[f] + ": expected an integer, got \"" +
                           std::string(fields[f]) + "\"");
  Row row;
  row.line = line_number;
  for (int k = 0; k < 3; ++k) {
    bool numerator_exact = false, denominator_exact = false;
    const double numerator = integer_to_double(fields[2 * k], numerator_exact);
    const double denominator = integer_to_double(fields[2 * k + 1], denominator_exact);
    if (denominator == 0)
      throw InputError(source, where,
                       std::string("field ") + kFieldNames[2 * k + 1] +
                           ": expected a nonzero denominator, got \"" +
                           std::string(fields[2 * k + 1]) + "\"");
    const double value = numerator / denominator;
    if (!std::isfinite(numerator) || !std::isfinite(denominator) || !std::isfinite(value))
      throw InputError(
          source, where,
          std::string("field ") + kFieldNames[2 * k] + ": the coordinate does not fit in a double");
    // The quotient is exact when value·denominator − numerator is 0.
    if (!numerator_exact || !denominator_exact || std::fma(value, denominator, -numerator) != 0)
      ++inexact_coordinates;
    row.point[k] = value;
  }
  if (fields[6] != "0" && fields[6] != "1")
    throw InputError(source, where,
                     "field truth: expected 0 or 1, got \"" + std::string(fields[6]) + "\"");
  row.truth = fields[6] == "1" ? 1 : 0;
  return row;
}

}  // namespace

const char* ccd_query_kind_name(CcdQueryKind kind) {
  return kind == CcdQueryKind::kVertexFace ? "vertex_face" : "edge_edge";
}

std::optional<CcdQueryKind> ccd_query_kind_from_path(const std::filesystem::path& path) {
  const std::filesystem::path absolute = std::filesystem::absolute(path).lexically_normal();
  std::vector<std::string> components;
  for (const auto& part : absolute) components.push_back(part.string());
  for (auto it = components.rbegin(); it != components.rend(); ++it) {
    const bool vertex_face = it->find("vertex-face") != std::string::npos ||
                             it->find("vertex_face") != std::string::npos;
    const bool edge_edge =
        it->find("edge-edge") != std::string::npos || it->find("edge_edge") != std::string::npos;
    if (vertex_face && edge_edge) return std::nullopt;
    if (vertex_face) return CcdQueryKind::kVertexFace;
    if (edge_edge) return CcdQueryKind::kEdgeEdge;
  }
  return std::nullopt;
}

CcdQueryFile read_ccd_query_file(const std::filesystem::path& path) {
  const std::string source = path.string();
  CcdQueryFile file;
  file.path = path;
  const std::optional<CcdQueryKind> kind = ccd_query_kind_from_path(path);
  if (!kind)
    throw InputError(source, "",
                     "cannot tell the query kind: expected a folder or file name containing "
                     "\"vertex-face\" or \"edge-edge\" (e.g. .../vertex-face/data_0_0.csv)");
  file.kind = *kind;
  require_regular_file(path, "a CCD query file");
  std::ifstream in(path);
  if (!in) throw InputError(source, "", "cannot open the file for reading");

  std::vector<Row> rows;
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (trimmed(line).empty()) continue;
    rows.push_back(parse_row(source, line_number, line, file.inexact_coordinates));
  }
  if (rows.empty())
    throw InputError(source, "line 1", "expected at least one query (8 rows), found none");
  if (rows.size() % 8 != 0) {
    const std::size_t incomplete = rows.size() - rows.size() % 8;
    throw InputError(source, "line " + std::to_string(rows[incomplete].line),
                     "expected 8 rows per query, but the last query has only " +
                         std::to_string(rows.size() % 8) + " (" + std::to_string(rows.size()) +
                         " rows in the file)");
  }
  for (std::size_t first = 0; first < rows.size(); first += 8) {
    LabelledCcdQuery labelled;
    labelled.first_line = rows[first].line;
    labelled.collides = rows[first].truth == 1;
    for (int i = 0; i < 8; ++i) {
      const Row& row = rows[first + i];
      if (row.truth != rows[first].truth)
        throw InputError(source, "line " + std::to_string(row.line),
                         "field truth: expected the same value on all 8 rows of the query "
                         "starting at line " +
                             std::to_string(rows[first].line));
      (i < 4 ? labelled.query.start[i] : labelled.query.end[i - 4]) = row.point;
    }
    file.queries.push_back(labelled);
  }
  return file;
}

}  // namespace hb
