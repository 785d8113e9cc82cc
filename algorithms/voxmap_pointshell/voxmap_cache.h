// Where the voxmap and pointshell caches live and how their files are named.
// A cache file's name is a hash of a key text that spells out everything the
// structure depends on (geometry hashes, poses, sizes, variant, region);
// the key text is also stored inside the file and checked on load.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "algorithms/core/content_hash.h"
#include "algorithms/core/pose.h"
#include "algorithms/core/triangle_mesh.h"

namespace hb {

/// Exact text of a pose: p then qw, qx, qy, qz.
std::string exact_key_text(const Pose& pose);

/// `<folder>/<prefix>-<hash of key>.hbcache` (voxmap.cpp writes it: a
/// header with the key and a hash, then the grids as an OpenVDB stream).
std::filesystem::path cache_file_path(const std::filesystem::path& folder,
                                      const std::string& prefix, const std::string& key);

/// A fresh name next to `target` for writing before the rename into place:
/// unique per process and call.
std::filesystem::path temporary_sibling(const std::filesystem::path& target);

}  // namespace hb
