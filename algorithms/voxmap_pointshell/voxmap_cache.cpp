#include "algorithms/voxmap_pointshell/voxmap_cache.h"

#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <string_view>

#include "algorithms/core/content_hash.h"

namespace hb {

std::string exact_key_text(const Pose& pose) {
  std::string text;
  for (double v :
       {pose.p.x(), pose.p.y(), pose.p.z(), pose.q.w(), pose.q.x(), pose.q.y(), pose.q.z()})
    text += exact_key_text(v) + " ";
  return text;
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
