// A keyed, checksummed cache of built structures on disk, shared by every
// algorithm that preprocesses (voxmaps, pointshells, convex hierarchies,
// bounding-sphere trees). One file per key:
//   <folder>/<kind>-<hash of key>.hbcache
// holding a text header "hapticbench-cache 3 <kind>\n<key bytes> <payload
// bytes> <payload checksum>\n", the key, then the payload. The key spells out
// everything the structure depends on (content hashes, poses, settings,
// format versions) and is compared on read; a missing, truncated, damaged
// or different file is a miss, with the reason. Files are written under a
// temporary name beside the target and renamed into place, so that a reader
// (another process included) sees a whole file or none.
#pragma once

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "hapticbench/pose.h"

namespace hb {

class DiskCache {
 public:
  /// `folder` nullopt: caching off (every read misses, writes do nothing).
  /// `kind` names the files and is checked on read, e.g. "voxmap".
  DiskCache(std::optional<std::filesystem::path> folder, std::string kind);

  struct Lookup {
    /// The stored payload on a hit: a view of the file mapped into memory,
    /// valid while this Lookup lives (nothing is copied).
    std::optional<std::string_view> payload;
    std::string problem;                  ///< why an existing file was not used; empty otherwise
    std::shared_ptr<const void> mapping;  ///< keeps the file mapped
  };

  /// The payload stored under `key`.
  Lookup read(const std::string& key) const;
  /// Stores `payload` under `key`. Returns "" or what went wrong (the cache
  /// is an optimisation: a failed write never fails the caller).
  std::string write(const std::string& key, std::string_view payload) const;

  bool enabled() const { return folder_.has_value(); }
  /// The file for `key`; empty when caching is off.
  std::filesystem::path path_of(const std::string& key) const;

 private:
  std::optional<std::filesystem::path> folder_;
  std::string kind_;
};

/// Exact text of a pose for cache keys: p then qw, qx, qy, qz, each exact.
std::string exact_key_text(const Pose& pose);

}  // namespace hb
