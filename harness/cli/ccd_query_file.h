// Reader of primitive CCD query files (the format of the shared
// ccd-sample-queries data): 8 rows per query of exact rational coordinates
// `xnum,xden,ynum,yden,znum,zden,truth`, the kind of query told by the
// file's folder or name.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "algorithms/ccd/ccd_primitives.h"

namespace hb {

/// Which primitive pair a query file holds.
enum class CcdQueryKind { kVertexFace, kEdgeEdge };

/// "vertex_face" or "edge_edge".
const char* ccd_query_kind_name(CcdQueryKind kind);

/// The kind named by the nearest path component (the file name first, then
/// its folders upwards) that contains "vertex-face"/"vertex_face" or
/// "edge-edge"/"edge_edge"; nullopt when none does, or one names both.
std::optional<CcdQueryKind> ccd_query_kind_from_path(const std::filesystem::path& path);

/// One query with its ground truth.
struct LabelledCcdQuery {
  /// Row order of the file: vertex–face v, f0, f1, f2; edge–edge
  /// ea0, ea1, eb0, eb1 (start rows, then the same for end rows).
  LinearCcdQuery query;
  /// The primitives touch at some t in [0, 1] (exactly, in rationals).
  bool collides = false;
  /// 1-based line of the query's first row, for messages.
  int first_line = 0;
};

struct CcdQueryFile {
  std::filesystem::path path;
  CcdQueryKind kind = CcdQueryKind::kVertexFace;
  std::vector<LabelledCcdQuery> queries;
  /// Coordinates whose rational value is not a double and were rounded to
  /// nearest (the truth column may then not hold for the rounded query).
  int inexact_coordinates = 0;
};

/// Reads a query file. Throws InputError naming the file and line when it
/// cannot be read, its kind cannot be told from the path, a row is not 7
/// integers, a denominator is 0, a coordinate overflows a double, truth is
/// not 0/1 or differs within a query, or the row count is not a positive
/// multiple of 8.
CcdQueryFile read_ccd_query_file(const std::filesystem::path& path);

}  // namespace hb
