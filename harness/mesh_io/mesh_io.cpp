#include "harness/mesh_io/mesh_io.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <new>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "hapticbench/input_error.h"
#include "harness/mesh_io/mesh_formats.h"
#include "harness/process/memory_limit.h"

namespace hb {

namespace {

using mesh_formats::check_declared_count;
using mesh_formats::preview_text;
using mesh_formats::words_of;
using FilePoint = std::array<double, 3>;
using FilePolygon = std::vector<std::size_t>;

struct MeshFormat {
  const char* extension;  // lower case, with the dot
  const char* name;
};
constexpr std::array<MeshFormat, 4> kFormats = {
    {{".off", "OFF"}, {".obj", "OBJ"}, {".stl", "STL"}, {".ply", "PLY"}}};

const MeshFormat* format_of(const std::string& path, std::string& extension) {
  extension = std::filesystem::path(path).extension().string();
  std::string lower = extension;
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (const MeshFormat& format : kFormats)
    if (lower == format.extension) return &format;
  return nullptr;
}

std::string accepted_extensions() {
  std::string list;
  for (const MeshFormat& format : kFormats)
    list += (list.empty() ? "" : ", ") + std::string(format.extension);
  return list;
}

// Exact coordinates as a hash key; -0.0 and +0.0 are the same point.
struct ExactPoint {
  std::array<double, 3> xyz;
  bool operator==(const ExactPoint&) const = default;
};
struct ExactPointHash {
  std::size_t operator()(const ExactPoint& p) const {
    uint64_t h = 0xcbf29ce484222325ULL;
    for (double x : p.xyz) {
      h ^= std::bit_cast<uint64_t>(x + 0.0);  // x + 0.0 turns -0.0 into +0.0
      h *= 0x100000001b3ULL;
      h ^= h >> 29;
    }
    return static_cast<std::size_t>(h);
  }
};

// A line's number of words and the integer its first word starts with, as
// a stream reads it (an optional '+', digits, then anything: the readers
// take "2000000000" from "2000000000\x1f..." and stop there).
struct LineTokens {
  std::size_t count = 0;
  std::optional<long long> first_integer;
};
LineTokens tokens_of(const std::vector<std::string_view>& words) {
  LineTokens out;
  out.count = words.size();
  long long value = 0;
  if (!words.empty()) {
    std::string_view first = words[0];
    if (first.size() > 1 && first[0] == '+' && first[1] != '-') first.remove_prefix(1);
    const auto [end, error] = std::from_chars(first.data(), first.data() + first.size(), value);
    if (error == std::errc()) out.first_integer = value;
    if (error == std::errc::result_out_of_range)
      out.first_integer = std::numeric_limits<long long>::max();
  }
  return out;
}

// A face (or other list) line must list as many numbers as its first token
// declares: a face declaring 2e9 corners once made the reader zero-fill
// 16 GB before failing.
void check_list_line(const std::string& path, std::size_t line_number, const LineTokens& tokens) {
  if (!tokens.first_integer) return;  // not a number: the reader reports it
  const long long declared = *tokens.first_integer;
  if (declared < 0 || static_cast<unsigned long long>(declared) > tokens.count - 1)
    throw InputError(path, "line " + std::to_string(line_number),
                     "a face declares " + std::to_string(declared) +
                         " corners but the line lists " + std::to_string(tokens.count - 1) +
                         " numbers");
}

// An OFF vertex line starts with three finite coordinates (colours may follow).
void check_off_vertex_line(const std::string& path, std::size_t line_number,
                           const std::vector<std::string_view>& words) {
  bool ok = words.size() >= 3;
  for (std::size_t k = 0; ok && k < 3; ++k) {
    double value = 0;
    const auto [end, error] =
        std::from_chars(words[k].data(), words[k].data() + words[k].size(), value);
    ok = error == std::errc() && end == words[k].data() + words[k].size() && std::isfinite(value);
  }
  if (!ok) {
    std::string line;
    for (std::string_view word : words) line.append(line.empty() ? "" : " ").append(word);
    throw InputError(path, "line " + std::to_string(line_number),
                     "expected a vertex: three finite coordinates, got " + preview_text(line));
  }
}

// An OFF face's indices name declared vertices.
void check_off_face_indices(const std::string& path, std::size_t line_number,
                            const std::vector<std::string_view>& words, std::size_t vertices) {
  long long corners = 0;
  if (words.empty() ||
      std::from_chars(words[0].data(), words[0].data() + words[0].size(), corners).ec !=
          std::errc())
    return;
  for (long long k = 1; k <= corners && static_cast<std::size_t>(k) < words.size(); ++k) {
    const std::string_view word = words[static_cast<std::size_t>(k)];
    long long index = -1;
    const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), index);
    if (error != std::errc() || end != word.data() + word.size() || index < 0 ||
        static_cast<unsigned long long>(index) >= vertices)
      throw InputError(path, "line " + std::to_string(line_number),
                       "vertex index " + std::string(word) +
                           " is not one of the file's vertices (0 to " +
                           std::to_string(vertices == 0 ? 0 : vertices - 1) + ")");
  }
}

// The counts in an OFF header ("[C][N][4]OFF" then "vertices faces edges",
// '#' comments allowed), and every face line against the corners it
// declares.
void check_off_header(const std::string& path, std::uintmax_t file_bytes) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  std::size_t line_number = 0;
  // The header's words as the reader takes them: a keyword is its word's
  // leading letters and digits, and the character after them is consumed
  // ("OFF>3" is OFF then 3, "BINARY]" is BINARY; found by fuzzing).
  const auto keyword = [](const std::string& token) {
    const auto end =
        std::find_if(token.begin(), token.end(), [](unsigned char c) { return !std::isalnum(c); });
    return std::string(token.begin(), end);
  };
  std::vector<std::string> tokens;
  while (tokens.size() < 4 && std::getline(in, line)) {
    ++line_number;
    line = line.substr(0, line.find('#'));
    std::istringstream words(line);
    for (std::string word; tokens.size() < 4 && words >> word;) {
      if (!tokens.empty()) {
        tokens.push_back(word);
        continue;
      }
      tokens.push_back(keyword(word));
      if (tokens[0].size() + 1 < word.size()) tokens.push_back(word.substr(tokens[0].size() + 1));
    }
  }
  if (tokens.empty() || tokens[0].find("OFF") == std::string::npos) return;
  // Binary OFF ("OFF BINARY"): its counts are raw integers the checks
  // below cannot read, and the reader trusted them (found by fuzzing: a
  // 200-byte file made it allocate 4 GB). Text OFF is what OFF files are.
  if (tokens[0].find("BINARY") != std::string::npos ||
      (tokens.size() > 1 && keyword(tokens[1]) == "BINARY"))
    throw InputError(path, "line 1",
                     "binary OFF is not read; convert the mesh to text OFF, PLY, OBJ or STL");
  long double counts[2] = {0, 0};
  const char* names[] = {"vertices", "faces"};
  for (std::size_t k = 1; k < 3 && k < tokens.size(); ++k) {
    std::istringstream number(tokens[k]);
    if (!(number >> counts[k - 1])) return;  // the reader reports it
    check_declared_count(path, names[k - 1], counts[k - 1], file_bytes);
  }
  if (tokens.size() < 4) return;
  const auto vertex_lines = static_cast<std::size_t>(counts[0]);
  const auto face_lines = static_cast<std::size_t>(counts[1]);
  std::size_t vertices = 0, faces = 0;
  while (faces < face_lines && std::getline(in, line)) {
    ++line_number;
    const std::vector<std::string_view> words = words_of(line);
    const LineTokens line_tokens = tokens_of(words);
    if (line_tokens.count == 0) continue;
    if (vertices < vertex_lines) {
      ++vertices;
      check_off_vertex_line(path, line_number, words);
      continue;
    }
    ++faces;
    check_list_line(path, line_number, line_tokens);
    check_off_face_indices(path, line_number, words, vertex_lines);
  }
}

// Text OFF, read here rather than by a library's reader: one reader, so
// that what the checks above accept is exactly what is read (a vertex line
// with an extra number once shifted CGAL's reading of every face after it,
// and a face then declared 2e9 corners), and nothing is allocated beyond what the
// file's bytes can hold. Lines: the header keyword ([ST][C][N]OFF; the 4
// and n variants are refused), the counts, one vertex per line (three
// coordinates; colours or normals after them are ignored), one face per
// line (a count k, k vertex indices, an optional colour). Returns false
// when the file is not text OFF of that form (the caller reports it).
bool read_off_text(const std::string& path, std::uintmax_t file_bytes,
                   std::vector<FilePoint>& points, std::vector<FilePolygon>& polygons) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  std::size_t line_number = 0;
  // Keyword, vertex and face counts (an edge count may follow them on
  // their line): whole lines until the three are read.
  std::vector<std::string> header_storage;
  while (header_storage.size() < 3 && std::getline(in, line)) {
    ++line_number;
    for (std::string_view word : words_of(line)) header_storage.emplace_back(word);
  }
  if (header_storage.size() < 3) return false;
  const std::string& keyword = header_storage[0];
  if (keyword.size() < 3 || keyword.compare(keyword.size() - 3, 3, "OFF") != 0 ||
      keyword.find_first_not_of("STCNOF") != std::string::npos)
    throw InputError(path, "line 1",
                     "expected the keyword OFF (or COFF, NOFF, STOFF ...), got \"" +
                         keyword.substr(0, 40) + "\"; 4OFF and nOFF are not read");
  std::size_t counts[2] = {0, 0};
  for (int k = 0; k < 2; ++k) {
    const std::string& word = header_storage[1 + k];
    const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), counts[k]);
    if (error != std::errc() || end != word.data() + word.size())
      throw InputError(path, "header",
                       std::string("expected the number of ") + (k == 0 ? "vertices" : "faces") +
                           ", got \"" + word.substr(0, 40) + "\"");
  }
  // Each vertex line takes at least 6 bytes ("0 0 0\n") and each face 8.
  points.reserve(std::min<std::uintmax_t>(counts[0], file_bytes / 6));
  polygons.reserve(std::min<std::uintmax_t>(counts[1], file_bytes / 8));
  while ((points.size() < counts[0] || polygons.size() < counts[1]) && std::getline(in, line)) {
    ++line_number;
    const std::vector<std::string_view> words = words_of(line);
    if (words.empty()) continue;
    if (points.size() < counts[0]) {
      check_off_vertex_line(path, line_number, words);
      double xyz[3];
      for (int k = 0; k < 3; ++k)
        std::from_chars(words[k].data(), words[k].data() + words[k].size(), xyz[k]);
      points.push_back({xyz[0], xyz[1], xyz[2]});
      continue;
    }
    const LineTokens tokens = tokens_of(words);
    if (!tokens.first_integer)
      throw InputError(path, "line " + std::to_string(line_number),
                       "expected a face: a number of corners, then the vertex indices");
    check_list_line(path, line_number, tokens);
    check_off_face_indices(path, line_number, words, counts[0]);
    FilePolygon polygon(static_cast<std::size_t>(*tokens.first_integer));
    for (std::size_t k = 0; k < polygon.size(); ++k)
      std::from_chars(words[k + 1].data(), words[k + 1].data() + words[k + 1].size(), polygon[k]);
    polygons.push_back(std::move(polygon));
  }
  if (points.size() < counts[0] || polygons.size() < counts[1])
    throw InputError(path, "line " + std::to_string(line_number),
                     "the file ends after " + std::to_string(points.size()) + " of " +
                         std::to_string(counts[0]) + " vertices and " +
                         std::to_string(polygons.size()) + " of " + std::to_string(counts[1]) +
                         " faces its header declares");
  return true;
}

}  // namespace

TriangleMesh read_mesh_file(const std::string& path, double scale) {
  if (!std::isfinite(scale) || scale <= 0.0) {
    std::ostringstream got;
    got << scale;
    throw InputError(path, "scale",
                     "expected a positive finite scale (metres per file unit), got " + got.str());
  }
  std::error_code error;
  if (!std::filesystem::exists(path, error)) throw InputError(path, "", "file not found");
  if (!std::filesystem::is_regular_file(path, error))
    throw InputError(path, "", "not a regular file; expected a mesh file");

  std::string extension;
  const MeshFormat* format = format_of(path, extension);
  if (!format) {
    throw InputError(path, "",
                     "unknown mesh file extension \"" + extension + "\"; expected one of " +
                         accepted_extensions());
  }

  const std::uintmax_t file_bytes = std::filesystem::file_size(path, error);
  if (error) throw InputError(path, "", "cannot read the file's size: " + error.message());
  if (std::string(format->name) == "OFF") check_off_header(path, file_bytes);

  mesh_formats::PolygonSoup soup;
  std::vector<FilePoint>& points = soup.points;
  std::vector<FilePolygon>& polygons = soup.polygons;
  bool parsed = true;
  try {
    const std::string name = format->name;
    if (name == "OFF") parsed = read_off_text(path, file_bytes, points, polygons);
    if (name == "OBJ") mesh_formats::read_obj(path, soup);
    if (name == "STL") mesh_formats::read_stl(path, file_bytes, soup);
    if (name == "PLY") mesh_formats::read_ply(path, file_bytes, soup);
  } catch (const std::bad_alloc&) {
    // e.g. a face whose declared number of corners is absurd
    throw InputError(
        path, "",
        "declares more data than fits in memory (a corrupt count?): " + memory_limit_message());
  } catch (const std::length_error&) {
    throw InputError(path, "", "declares more data than fits in memory (a corrupt count?)");
  }
  if (!parsed || polygons.empty()) {
    throw InputError(path, "",
                     std::string("could not parse as ") + format->name +
                         (polygons.empty() ? " (no faces read)" : ""));
  }

  // Merge exactly coincident vertices: STL stores every triangle with its own
  // copies of its corners, and other exporters sometimes do the same.
  TriangleMesh mesh;
  std::vector<int> merged_index(points.size());
  std::unordered_map<ExactPoint, int, ExactPointHash> index_of_point;
  index_of_point.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const ExactPoint key{{points[i][0] + 0.0, points[i][1] + 0.0, points[i][2] + 0.0}};
    const auto [it, inserted] =
        index_of_point.try_emplace(key, static_cast<int>(mesh.vertices.size()));
    if (inserted) mesh.vertices.emplace_back(scale * Vec3(key.xyz[0], key.xyz[1], key.xyz[2]));
    merged_index[i] = it->second;
  }

  // Polygons become triangle fans from their first corner: exact for convex
  // polygons (what exporters write); a concave polygon may fold, which
  // validation then reports.
  mesh.triangles.reserve(polygons.size());
  for (std::size_t f = 0; f < polygons.size(); ++f) {
    const FilePolygon& polygon = polygons[f];
    if (polygon.size() < 3) {
      throw InputError(path, "face " + std::to_string(f),
                       "has " + std::to_string(polygon.size()) + " vertices; expected at least 3");
    }
    for (std::size_t index : polygon) {
      if (index >= points.size()) {
        throw InputError(path, "face " + std::to_string(f),
                         "vertex index " + std::to_string(index) +
                             " is out of range; the file has " + std::to_string(points.size()) +
                             " vertices");
      }
    }
    for (std::size_t corner = 1; corner + 1 < polygon.size(); ++corner) {
      mesh.triangles.push_back({merged_index[polygon[0]], merged_index[polygon[corner]],
                                merged_index[polygon[corner + 1]]});
    }
  }
  return mesh;
}

}  // namespace hb
