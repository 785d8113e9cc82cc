// Content hashes for cache keys and run provenance (FNV-1a, 64 bit, hex).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "hapticbench/triangle_mesh.h"

namespace hb {

/// Incremental FNV-1a 64-bit hash.
class ContentHash {
 public:
  ContentHash& add(std::string_view bytes) {
    for (unsigned char c : bytes) {
      state_ ^= c;
      state_ *= 0x100000001b3ULL;
    }
    return *this;
  }
  uint64_t value() const { return state_; }
  /// 16 lowercase hex digits.
  std::string hex() const;

 private:
  uint64_t state_ = 0xcbf29ce484222325ULL;
};

/// Exact text of a double (hexadecimal floating point), for cache keys.
std::string exact_key_text(double value);

/// Hash (hex) of a mesh's vertices and triangles as stored.
std::string mesh_geometry_hash(const TriangleMesh& mesh);

/// Hash of a file's bytes as hex; throws InputError naming the file if unreadable.
std::string file_content_hash(const std::string& path);

}  // namespace hb
