// A keyed, checksummed cache of built structures on disk, shared by every
// algorithm that preprocesses (voxmaps, pointshells, convex hierarchies,
// bounding-sphere trees). One file per key:
//   <folder>/<kind>-<hash of key>.hbcache
// holding a text header "hapticbench-cache 3 <kind>\n<key bytes> <payload
// bytes> <payload checksum>\n", the key, then the payload. The key spells out
// everything the structure depends on (content hashes, poses, settings,
// format versions) and is compared on read; a missing, truncated, damaged
// or different file is a miss, with the reason. Files are written under a
// temporary name beside the target, created exclusively, and renamed into
// place, so that a reader (another process included) sees a whole file or
// none. The checksum catches accidents only (anyone can recompute it): a
// file is used only when this user (or root) wrote it, nobody else can
// write it, and its folder is not one other users can change.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
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
  /// Reads the payload stored under `key` in parts of at most kPartBytes,
  /// handed to `consume` in order, without holding the whole in memory.
  /// True on a hit; false on a miss, with `problem` set when a file was
  /// there but not used. The checksum is known only at the end: after a
  /// false, discard what `consume` was given.
  bool read_parts(const std::string& key, const std::function<void(std::string_view)>& consume,
                  std::string* problem = nullptr) const;
  static constexpr std::size_t kPartBytes = std::size_t{1} << 20;

  /// Stores `payload` under `key`. Returns "" or what went wrong (the cache
  /// is an optimisation: a failed write never fails the caller).
  std::string write(const std::string& key, std::string_view payload) const;
  /// Hands each part of a payload to `put`, in order.
  using PartsProducer = std::function<void(const std::function<void(std::string_view)>& put)>;
  /// Stores a payload of `payload_bytes` bytes that `produce` gives in parts;
  /// `produce` is called twice (the checksum precedes the payload in the
  /// file) and must give the same bytes both times. Memory: one part.
  std::string write_parts(const std::string& key, std::uint64_t payload_bytes,
                          const PartsProducer& produce) const;

  bool enabled() const { return folder_.has_value(); }
  /// The file for `key`; empty when caching is off.
  std::filesystem::path path_of(const std::string& key) const;

 private:
  struct OpenedFile;
  /// Opens the file for `key` and checks who wrote it, its header and its
  /// key; false on a miss (file.problem says why when one was there).
  bool open_checked(const std::string& key, OpenedFile& file) const;

  std::optional<std::filesystem::path> folder_;
  std::string kind_;
};

/// Exact text of a pose for cache keys: p then qw, qx, qy, qz, each exact.
std::string exact_key_text(const Pose& pose);

}  // namespace hb
