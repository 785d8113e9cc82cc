#include "algorithms/voxmap_pointshell/voxmap_cache.h"

#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <string_view>

#include "algorithms/core/content_hash.h"

namespace hb {

std::string exact_key_text(double value) {
  char text[64];
  std::snprintf(text, sizeof text, "%a", value);
  return text;
}

std::string exact_key_text(const Pose& pose) {
  std::string text;
  for (double v :
       {pose.p.x(), pose.p.y(), pose.p.z(), pose.q.w(), pose.q.x(), pose.q.y(), pose.q.z()})
    text += exact_key_text(v) + " ";
  return text;
}

std::string mesh_geometry_hash(const TriangleMesh& mesh) {
  ContentHash hash;
  hash.add(std::string_view(reinterpret_cast<const char*>(mesh.vertices.data()),
                            mesh.vertices.size() * sizeof(Vec3)));
  hash.add(std::string_view(reinterpret_cast<const char*>(mesh.triangles.data()),
                            mesh.triangles.size() * sizeof(mesh.triangles[0])));
  return hash.hex();
}

std::filesystem::path cache_file_path(const std::filesystem::path& folder,
                                      const std::string& prefix, const std::string& key) {
  return folder / (prefix + "-" + ContentHash().add(key).hex() + ".hbcache");
}

std::filesystem::path temporary_sibling(const std::filesystem::path& target) {
  static std::atomic<unsigned> counter{0};
  return target.parent_path() / (target.filename().string() + ".tmp-" + std::to_string(::getpid()) +
                                 "-" + std::to_string(counter++));
}

}  // namespace hb
