// The mesh file readers behind read_mesh_file (mesh_io.h): strict readers
// that trust no count a file declares. Every allocation is bounded by the
// bytes left in the file (a face line cannot declare more corners than it
// has words, a binary element count must fit the remaining bytes), so that
// reading keeps the memory rule of harness/process/memory_limit.h
// (kInputMemoryPerByte, docs/limits.md, "Memory").
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace hb::mesh_formats {

/// A file's vertices (file units) and polygons (indices into the vertices,
/// not yet checked against their count), as the file lists them.
struct PolygonSoup {
  std::vector<std::array<double, 3>> points;
  std::vector<std::vector<std::size_t>> polygons;
};

/// The most vertices, or faces, a mesh file may declare.
constexpr std::uintmax_t kMaxMeshElements = 20'000'000;

/// Whitespace-separated words of a line up to a '#' comment.
std::vector<std::string_view> words_of(std::string_view line);
/// The first 60 characters of a line, quoted, for an error message.
std::string preview_text(std::string_view line);
/// Refuses a declared element count that `file_bytes` cannot hold at two
/// bytes an element (a number and a separator), or above kMaxMeshElements.
void check_declared_count(const std::string& path, const std::string& what, long double count,
                          std::uintmax_t file_bytes);

/// Wavefront OBJ: "v x y z" vertices and "f i j k ..." faces (corners
/// "i", "i/t", "i/t/n" or "i//n", 1-based or negative = relative to the
/// last vertex); every other statement is skipped.
void read_obj(const std::string& path, PolygonSoup& soup);
/// STL, binary (80-byte header, 32-bit count, 50 bytes a triangle) or ASCII
/// ("solid", then facets of "outer loop", three "vertex x y z", "endloop").
/// A file starting with "solid" whose size is exactly that of the binary
/// layout for its count is binary (some exporters write "solid" there).
void read_stl(const std::string& path, std::uintmax_t file_bytes, PolygonSoup& soup);
/// PLY 1.0, ascii or binary (either byte order): a "vertex" element with
/// float or double x, y, z, a "face" element with a list property
/// "vertex_indices" (or "vertex_index"); other elements and properties are
/// read and skipped.
void read_ply(const std::string& path, std::uintmax_t file_bytes, PolygonSoup& soup);

}  // namespace hb::mesh_formats
