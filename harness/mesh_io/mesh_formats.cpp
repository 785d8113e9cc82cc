#include "harness/mesh_io/mesh_formats.h"

#include <algorithm>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <iterator>
#include <optional>
#include <sstream>

#include "hapticbench/input_error.h"

namespace hb::mesh_formats {

namespace {

std::string line_place(std::size_t line_number) { return "line " + std::to_string(line_number); }

// The whole word as a finite number, or nothing.
std::optional<double> finite_number(std::string_view word) {
  double value = 0;
  const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), value);
  if (error != std::errc() || end != word.data() + word.size() || !std::isfinite(value))
    return std::nullopt;
  return value;
}

// The whole word as an integer, or nothing.
std::optional<long long> integer(std::string_view word) {
  long long value = 0;
  const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), value);
  if (error != std::errc() || end != word.data() + word.size()) return std::nullopt;
  return value;
}

void add_point(const std::string& path, const std::string& place, PolygonSoup& soup,
               const std::array<double, 3>& xyz) {
  if (soup.points.size() >= kMaxMeshElements)
    throw InputError(path, place,
                     "more than " + std::to_string(kMaxMeshElements) +
                         " vertices (hapticbench reads at most that many per mesh)");
  soup.points.push_back(xyz);
}

void add_polygon(const std::string& path, const std::string& place, PolygonSoup& soup,
                 std::vector<std::size_t> polygon) {
  if (soup.polygons.size() >= kMaxMeshElements)
    throw InputError(path, place,
                     "more than " + std::to_string(kMaxMeshElements) +
                         " faces (hapticbench reads at most that many per mesh)");
  soup.polygons.push_back(std::move(polygon));
}

// ---- OBJ --------------------------------------------------------------------

// The vertex of an OBJ face corner ("i", "i/t", "i/t/n", "i//n"): 1-based,
// or negative counting back from the last vertex read.
std::size_t obj_corner(const std::string& path, std::size_t line_number, std::string_view word,
                       std::size_t vertices_so_far) {
  const std::optional<long long> index = integer(word.substr(0, word.find('/')));
  const auto refuse = [&](const std::string& why) -> std::size_t {
    throw InputError(path, line_place(line_number),
                     "face corner \"" + std::string(word.substr(0, 40)) + "\" " + why);
  };
  if (!index || *index == 0) return refuse("is not a vertex number (1, 2, ... or -1, -2, ...)");
  if (*index > 0) return static_cast<std::size_t>(*index - 1);  // range checked by the caller
  if (static_cast<unsigned long long>(-(*index + 1)) >= vertices_so_far)
    return refuse("counts back past the first vertex (" + std::to_string(vertices_so_far) +
                  " read so far)");
  return vertices_so_far - static_cast<std::size_t>(-*index);
}

// ---- Binary layouts ---------------------------------------------------------

enum class ByteOrder { kLittle, kBig };

// An unsigned integer of `size` bytes at `at`.
uint64_t unsigned_at(const char* at, int size, ByteOrder order) {
  uint64_t value = 0;
  for (int k = 0; k < size; ++k) {
    const int byte = order == ByteOrder::kLittle ? size - 1 - k : k;
    value = (value << 8) | static_cast<unsigned char>(at[byte]);
  }
  return value;
}

float float_at(const char* at, ByteOrder order) {
  return std::bit_cast<float>(static_cast<uint32_t>(unsigned_at(at, 4, order)));
}

// ---- PLY --------------------------------------------------------------------

enum class PlyType { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

std::optional<PlyType> ply_type(const std::string& name) {
  static const std::pair<const char*, PlyType> kNames[] = {
      {"char", PlyType::kInt8},      {"int8", PlyType::kInt8},       {"uchar", PlyType::kUint8},
      {"uint8", PlyType::kUint8},    {"short", PlyType::kInt16},     {"int16", PlyType::kInt16},
      {"ushort", PlyType::kUint16},  {"uint16", PlyType::kUint16},   {"int", PlyType::kInt32},
      {"int32", PlyType::kInt32},    {"uint", PlyType::kUint32},     {"uint32", PlyType::kUint32},
      {"float", PlyType::kFloat32},  {"float32", PlyType::kFloat32}, {"double", PlyType::kFloat64},
      {"float64", PlyType::kFloat64}};
  for (const auto& [text, type] : kNames)
    if (name == text) return type;
  return std::nullopt;
}

int ply_size(PlyType type) {
  switch (type) {
    case PlyType::kInt8:
    case PlyType::kUint8:
      return 1;
    case PlyType::kInt16:
    case PlyType::kUint16:
      return 2;
    case PlyType::kInt32:
    case PlyType::kUint32:
    case PlyType::kFloat32:
      return 4;
    case PlyType::kFloat64:
      return 8;
  }
  return 8;
}

bool ply_integral(PlyType type) { return type != PlyType::kFloat32 && type != PlyType::kFloat64; }

double ply_binary_value(const char* at, PlyType type, ByteOrder order) {
  const uint64_t bits = unsigned_at(at, ply_size(type), order);
  switch (type) {
    case PlyType::kInt8:
      return static_cast<int8_t>(bits);
    case PlyType::kUint8:
      return static_cast<uint8_t>(bits);
    case PlyType::kInt16:
      return static_cast<int16_t>(bits);
    case PlyType::kUint16:
      return static_cast<uint16_t>(bits);
    case PlyType::kInt32:
      return static_cast<int32_t>(bits);
    case PlyType::kUint32:
      return static_cast<uint32_t>(bits);
    case PlyType::kFloat32:
      return std::bit_cast<float>(static_cast<uint32_t>(bits));
    case PlyType::kFloat64:
      return std::bit_cast<double>(bits);
  }
  return 0;
}

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::kFloat32;   // of the values (a list's entries)
  std::optional<PlyType> count_type;  // a list's length
};

struct PlyElement {
  std::string name;
  std::uintmax_t count = 0;
  std::vector<PlyProperty> properties;
  // Bytes an element takes at least in a binary file (a list may be empty).
  std::uintmax_t min_binary_bytes() const {
    std::uintmax_t bytes = 0;
    for (const PlyProperty& p : properties)
      bytes += static_cast<std::uintmax_t>(ply_size(p.count_type ? *p.count_type : p.type));
    return bytes;
  }
};

struct PlyHeader {
  enum class Format { kAscii, kBinaryLittle, kBinaryBig } format = Format::kAscii;
  std::vector<PlyElement> elements;
  std::size_t lines = 0;  // header lines, "end_header" included
};

PlyHeader read_ply_header(const std::string& path, std::istream& in, std::uintmax_t file_bytes) {
  PlyHeader header;
  bool format_seen = false, ended = false;
  std::string line;
  std::size_t& line_number = header.lines;
  const auto header_error = [&](const std::string& why) {
    throw InputError(path, line_place(line_number), why);
  };
  while (line_number < 1000 && std::getline(in, line)) {
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::vector<std::string_view> words = words_of(line);
    const std::string keyword = words.empty() ? "" : std::string(words[0]);
    if (line_number == 1) {
      if (words.size() != 1 || words[0] != "ply")
        header_error("expected \"ply\" on the first line");
      continue;
    }
    if (keyword == "end_header") {
      ended = true;
      break;
    }
    if (keyword == "format") {
      if (words.size() != 3 || words[2] != "1.0")
        header_error("expected \"format ascii 1.0\" (or binary_little_endian, binary_big_endian)");
      if (words[1] == "ascii") {
        header.format = PlyHeader::Format::kAscii;
      } else if (words[1] == "binary_little_endian") {
        header.format = PlyHeader::Format::kBinaryLittle;
      } else if (words[1] == "binary_big_endian") {
        header.format = PlyHeader::Format::kBinaryBig;
      } else {
        header_error("unknown format \"" + std::string(words[1].substr(0, 40)) + "\"");
      }
      format_seen = true;
    } else if (keyword == "element") {
      long double count = -1;
      if (words.size() == 3) std::istringstream(std::string(words[2])) >> count;
      if (words.size() != 3 || count < 0 || count != std::floor(count))
        header_error("expected \"element NAME COUNT\", got " + preview_text(line));
      check_declared_count(path, "elements of \"" + std::string(words[1]) + "\"", count,
                           file_bytes);
      header.elements.push_back({std::string(words[1]), static_cast<std::uintmax_t>(count), {}});
    } else if (keyword == "property") {
      if (header.elements.empty()) header_error("a property before any element");
      PlyProperty property;
      const bool list = words.size() == 5 && words[1] == "list";
      if (words.size() != (list ? 5u : 3u))
        header_error("expected \"property TYPE NAME\" or \"property list COUNT_TYPE TYPE NAME\"");
      const std::string type_name(words[list ? 3 : 1]);
      const std::optional<PlyType> type = ply_type(type_name);
      if (!type) header_error("unknown property type \"" + type_name.substr(0, 40) + "\"");
      property.type = *type;
      property.name = std::string(words.back());
      if (list) {
        property.count_type = ply_type(std::string(words[2]));
        if (!property.count_type || !ply_integral(*property.count_type))
          header_error("a list's count type must be an integer type");
      }
      PlyElement& element = header.elements.back();
      // Vertex coordinates are float or double (an int16 "z" once crashed
      // the reader hapticbench used before; found by fuzzing).
      if (element.name == "vertex" && !list &&
          (property.name == "x" || property.name == "y" || property.name == "z") &&
          ply_integral(property.type))
        header_error("vertex coordinate \"" + property.name + "\" has type \"" + type_name +
                     "\"; expected float or double");
      element.properties.push_back(property);
    } else if (keyword != "comment" && keyword != "obj_info" && !keyword.empty()) {
      header_error("unknown header line " + preview_text(line) +
                   " (expected format, element, property, comment or end_header)");
    }
  }
  if (!ended) header_error("no \"end_header\" line in the first 1000 lines");
  if (!format_seen) header_error("no \"format\" line in the header");
  return header;
}

// What a PLY element's values become: the indices of x, y, z (vertex) or of
// the face list, or nothing (skipped).
struct PlyRoles {
  int x = -1, y = -1, z = -1, face_list = -1;
};

PlyRoles ply_roles(const PlyElement& element) {
  PlyRoles roles;
  for (std::size_t k = 0; k < element.properties.size(); ++k) {
    const PlyProperty& p = element.properties[k];
    const int index = static_cast<int>(k);
    if (element.name == "vertex" && !p.count_type) {
      if (p.name == "x") roles.x = index;
      if (p.name == "y") roles.y = index;
      if (p.name == "z") roles.z = index;
    }
    if (element.name == "face" && p.count_type &&
        (p.name == "vertex_indices" || p.name == "vertex_index"))
      roles.face_list = index;
  }
  return roles;
}

// One element's values, in property order; a list's entries follow its count.
struct PlyValues {
  std::vector<double> scalars;    // one per scalar property
  std::vector<std::size_t> face;  // the face list's entries, if any
  void clear() {
    scalars.clear();
    face.clear();
  }
};

// Stores one element's values (x, y, z and the face) into the soup.
void store_element(const std::string& path, const std::string& place, const PlyElement& element,
                   const PlyRoles& roles, const PlyValues& values, PolygonSoup& soup) {
  if (element.name == "vertex") {
    std::array<double, 3> xyz{};
    const int roles_xyz[3] = {roles.x, roles.y, roles.z};
    for (int a = 0; a < 3; ++a) {
      xyz[static_cast<std::size_t>(a)] = values.scalars[static_cast<std::size_t>(roles_xyz[a])];
      if (!std::isfinite(xyz[static_cast<std::size_t>(a)]))
        throw InputError(path, place, "a vertex coordinate is not a finite number");
    }
    add_point(path, place, soup, xyz);
  } else if (element.name == "face") {
    add_polygon(path, place, soup, values.face);
  }
}

// A list entry as a vertex index.
std::size_t ply_index(const std::string& path, const std::string& place, double value) {
  if (!(value >= 0) || value != std::floor(value) || value > 9.0e15)
    throw InputError(path, place, "a face's vertex index is not a non-negative integer");
  return static_cast<std::size_t>(value);
}

void read_ply_ascii(const std::string& path, std::istream& in, const PlyHeader& header,
                    PolygonSoup& soup) {
  std::string line;
  std::size_t line_number = header.lines;
  PlyValues values;
  for (const PlyElement& element : header.elements) {
    const PlyRoles roles = ply_roles(element);
    for (std::uintmax_t i = 0; i < element.count;) {
      if (!std::getline(in, line))
        throw InputError(path, line_place(line_number),
                         "the file ends after " + std::to_string(i) + " of the " +
                             std::to_string(element.count) + " \"" + element.name +
                             "\" elements its header declares");
      ++line_number;
      const std::vector<std::string_view> words = words_of(line);
      if (words.empty()) continue;
      ++i;
      const std::string place = line_place(line_number);
      const auto refuse = [&] {
        throw InputError(path, place,
                         "expected one \"" + element.name + "\" element (" +
                             std::to_string(element.properties.size()) + " properties), got " +
                             preview_text(line));
      };
      values.clear();
      std::size_t at = 0;
      for (std::size_t k = 0; k < element.properties.size(); ++k) {
        const PlyProperty& p = element.properties[k];
        if (at >= words.size()) refuse();
        if (!p.count_type) {
          double value = 0;
          const auto [end, error] =
              std::from_chars(words[at].data(), words[at].data() + words[at].size(), value);
          if (error != std::errc() || end != words[at].data() + words[at].size()) refuse();
          values.scalars.push_back(value);
          ++at;
          continue;
        }
        values.scalars.push_back(0);
        const std::optional<long long> count = integer(words[at++]);
        // A list cannot hold more entries than the words left on its line.
        if (!count || *count < 0 || static_cast<std::size_t>(*count) > words.size() - at)
          throw InputError(path, place,
                           "a list declares " + std::string(words[at - 1].substr(0, 20)) +
                               " entries but the line has " + std::to_string(words.size() - at) +
                               " words left");
        const bool is_face = static_cast<int>(k) == roles.face_list;
        for (long long e = 0; e < *count; ++e, ++at) {
          const std::optional<double> value = finite_number(words[at]);
          if (!value) refuse();
          if (is_face) values.face.push_back(ply_index(path, place, *value));
        }
      }
      if (at != words.size()) refuse();
      store_element(path, place, element, roles, values, soup);
    }
  }
}

void read_ply_binary(const std::string& path, std::istream& in, std::uintmax_t data_bytes,
                     const PlyHeader& header, PolygonSoup& soup) {
  // The data section, at most the file's size: within the memory rule.
  std::string data(static_cast<std::size_t>(data_bytes), '\0');
  in.read(data.data(), static_cast<std::streamsize>(data.size()));
  data.resize(static_cast<std::size_t>(in.gcount()));
  const ByteOrder order =
      header.format == PlyHeader::Format::kBinaryBig ? ByteOrder::kBig : ByteOrder::kLittle;
  std::size_t at = 0;
  PlyValues values;
  for (const PlyElement& element : header.elements) {
    const PlyRoles roles = ply_roles(element);
    const std::uintmax_t need = element.count * element.min_binary_bytes();
    if (element.min_binary_bytes() > 0 && need / element.min_binary_bytes() != element.count)
      throw InputError(path, "header", "element count overflows");
    if (need > data.size() - at)
      throw InputError(path, "element " + element.name,
                       "the header declares " + std::to_string(element.count) + " \"" +
                           element.name + "\" elements, which need at least " +
                           std::to_string(need) + " bytes; " + std::to_string(data.size() - at) +
                           " are left");
    for (std::uintmax_t i = 0; i < element.count; ++i) {
      const std::string place = "element " + element.name + " " + std::to_string(i);
      const auto take = [&](PlyType type) {
        const std::size_t size = static_cast<std::size_t>(ply_size(type));
        if (size > data.size() - at)
          throw InputError(path, place, "the file ends inside this element");
        const double value = ply_binary_value(data.data() + at, type, order);
        at += size;
        return value;
      };
      values.clear();
      for (std::size_t k = 0; k < element.properties.size(); ++k) {
        const PlyProperty& p = element.properties[k];
        if (!p.count_type) {
          values.scalars.push_back(take(p.type));
          continue;
        }
        values.scalars.push_back(0);
        const double count = take(*p.count_type);
        // A list cannot hold more entries than the bytes left.
        if (count < 0 || count > static_cast<double>((data.size() - at) /
                                                     static_cast<std::size_t>(ply_size(p.type))))
          throw InputError(path, place,
                           "a list declares " + std::to_string(static_cast<long long>(count)) +
                               " entries; " + std::to_string(data.size() - at) + " bytes are left");
        const bool is_face = static_cast<int>(k) == roles.face_list;
        for (long long e = 0; e < static_cast<long long>(count); ++e) {
          const double value = take(p.type);
          if (is_face) values.face.push_back(ply_index(path, place, value));
        }
      }
      store_element(path, place, element, roles, values, soup);
    }
  }
}

}  // namespace

std::vector<std::string_view> words_of(std::string_view line) {
  std::vector<std::string_view> words;
  std::size_t i = 0;
  while (i < line.size() && line[i] != '#') {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    if (i >= line.size() || line[i] == '#') break;
    const std::size_t start = i;
    while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i])) && line[i] != '#')
      ++i;
    words.push_back(line.substr(start, i - start));
  }
  return words;
}

std::string preview_text(std::string_view line) {
  std::string text(line.substr(0, 60));
  if (line.size() > 60) text += "...";
  return "\"" + text + "\"";
}

void check_declared_count(const std::string& path, const std::string& what, long double count,
                          std::uintmax_t file_bytes) {
  if (count < 0 || count > static_cast<long double>(file_bytes) / 2 ||
      count > static_cast<long double>(kMaxMeshElements)) {
    std::ostringstream text;
    text << std::fixed << std::setprecision(0) << "the header declares " << count << " " << what
         << ", but the file has only " << file_bytes << " bytes";
    if (count > static_cast<long double>(kMaxMeshElements))
      text << " (and hapticbench reads at most " << kMaxMeshElements << " per mesh)";
    throw InputError(path, "header", text.str());
  }
}

void read_obj(const std::string& path, PolygonSoup& soup) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  std::size_t line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    const std::vector<std::string_view> words = words_of(line);
    if (words.empty()) continue;
    if (words[0] == "v") {
      std::array<double, 3> xyz{};
      for (std::size_t a = 0; a < 3; ++a) {
        const std::optional<double> value =
            a + 1 < words.size() ? finite_number(words[a + 1]) : std::nullopt;
        if (!value)
          throw InputError(
              path, line_place(line_number),
              "expected a vertex: \"v\" and three finite coordinates, got " + preview_text(line));
        xyz[a] = *value;
      }
      add_point(path, line_place(line_number), soup, xyz);
    } else if (words[0] == "f") {
      std::vector<std::size_t> polygon;
      polygon.reserve(words.size() - 1);  // bounded by the line's words
      for (std::size_t k = 1; k < words.size(); ++k)
        polygon.push_back(obj_corner(path, line_number, words[k], soup.points.size()));
      add_polygon(path, line_place(line_number), soup, std::move(polygon));
    }
    // Other statements (vt, vn, g, o, s, usemtl, mtllib, l, p ...) carry
    // nothing a rigid body's surface needs.
  }
}

void read_stl(const std::string& path, std::uintmax_t file_bytes, PolygonSoup& soup) {
  std::ifstream in(path, std::ios::binary);
  char head[84] = {};
  in.read(head, sizeof head);
  const std::streamsize head_bytes = in.gcount();
  const uint32_t count =
      head_bytes == 84 ? static_cast<uint32_t>(unsigned_at(head + 80, 4, ByteOrder::kLittle)) : 0;
  const std::uintmax_t binary_bytes = 84 + 50 * static_cast<std::uintmax_t>(count);
  const bool says_solid = head_bytes >= 5 && std::string_view(head, 5) == "solid";
  if (!says_solid || (head_bytes == 84 && binary_bytes == file_bytes)) {
    // Binary: the count must fit the file (a 233-byte file declaring 8e8
    // triangles once kept a reader busy with them).
    if (head_bytes < 84)
      throw InputError(path, "", "a binary STL file needs at least 84 bytes (header and count)");
    if (binary_bytes > file_bytes)
      throw InputError(path, "triangle count",
                       "the binary STL header declares " + std::to_string(count) +
                           " triangles, which need " + std::to_string(binary_bytes) +
                           " bytes; the file has " + std::to_string(file_bytes));
    if (count > kMaxMeshElements)
      throw InputError(path, "triangle count",
                       std::to_string(count) + " triangles; hapticbench reads at most " +
                           std::to_string(kMaxMeshElements) + " per mesh");
    soup.points.reserve(3 * static_cast<std::size_t>(count));
    soup.polygons.reserve(count);
    char triangle[50];
    for (uint32_t t = 0; t < count; ++t) {
      in.read(triangle, sizeof triangle);
      std::vector<std::size_t> polygon;
      for (int corner = 0; corner < 3; ++corner) {
        std::array<double, 3> xyz{};
        for (int a = 0; a < 3; ++a) {
          xyz[static_cast<std::size_t>(a)] =
              float_at(triangle + 12 + 12 * corner + 4 * a, ByteOrder::kLittle);
          if (!std::isfinite(xyz[static_cast<std::size_t>(a)]))
            throw InputError(path, "triangle " + std::to_string(t),
                             "a corner coordinate is not a finite number");
        }
        polygon.push_back(soup.points.size());
        soup.points.push_back(xyz);
      }
      soup.polygons.push_back(std::move(polygon));
    }
    return;
  }
  // ASCII: keywords line by line; a facet's loop holds exactly three vertices.
  in.clear();
  in.seekg(0);
  std::string line;
  std::size_t line_number = 0;
  std::vector<std::size_t> loop;
  while (std::getline(in, line)) {
    ++line_number;
    const std::vector<std::string_view> words = words_of(line);
    if (words.empty()) continue;
    const std::string place = line_place(line_number);
    const std::string_view keyword = words[0];
    if (keyword == "vertex") {
      std::array<double, 3> xyz{};
      for (std::size_t a = 0; a < 3; ++a) {
        const std::optional<double> value =
            a + 1 < words.size() ? finite_number(words[a + 1]) : std::nullopt;
        if (!value || words.size() != 4)
          throw InputError(
              path, place,
              "expected \"vertex\" and three finite coordinates, got " + preview_text(line));
        xyz[a] = *value;
      }
      if (loop.size() == 3)
        throw InputError(path, place, "a facet's loop lists more than three vertices");
      loop.push_back(soup.points.size());
      add_point(path, place, soup, xyz);
    } else if (keyword == "endloop") {
      if (loop.size() != 3)
        throw InputError(
            path, place,
            "a facet's loop lists " + std::to_string(loop.size()) + " vertices; expected three");
      add_polygon(path, place, soup, loop);
      loop.clear();
    } else if (keyword != "solid" && keyword != "facet" && keyword != "outer" &&
               keyword != "endfacet" && keyword != "endsolid") {
      throw InputError(path, place,
                       "expected solid, facet, outer loop, vertex, endloop, endfacet or endsolid, "
                       "got " +
                           preview_text(line));
    }
  }
}

void read_ply(const std::string& path, std::uintmax_t file_bytes, PolygonSoup& soup) {
  std::ifstream in(path, std::ios::binary);
  const PlyHeader header = read_ply_header(path, in, file_bytes);
  bool has_vertex = false;
  for (const PlyElement& element : header.elements) {
    const PlyRoles roles = ply_roles(element);
    if (element.name == "vertex") {
      has_vertex = true;
      if (roles.x < 0 || roles.y < 0 || roles.z < 0)
        throw InputError(path, "header", "the \"vertex\" element needs properties x, y and z");
    }
    if (element.name == "face" && roles.face_list < 0)
      throw InputError(path, "header",
                       "the \"face\" element needs a list property \"vertex_indices\"");
  }
  if (!has_vertex) throw InputError(path, "header", "no \"vertex\" element");
  if (header.format == PlyHeader::Format::kAscii) {
    read_ply_ascii(path, in, header, soup);
    return;
  }
  const std::streamoff data_start = in.tellg();
  if (data_start < 0) throw InputError(path, "", "the file ends after its header");
  read_ply_binary(path, in, file_bytes - static_cast<std::uintmax_t>(data_start), header, soup);
}

}  // namespace hb::mesh_formats
