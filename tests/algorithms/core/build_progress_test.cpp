// Build announcements reach the listener installed on this thread, and
// only while it is installed.
#include "algorithms/core/build_progress.h"

#include <catch2/catch.hpp>
#include <string>
#include <thread>
#include <vector>

namespace {
class Recorder : public hb::BuildProgressListener {
 public:
  void build_stage(std::string_view stage) override { said.emplace_back(stage); }
  void build_progress(std::size_t done, std::size_t total) override {
    said.push_back(std::to_string(done) + "/" + std::to_string(total));
  }
  std::vector<std::string> said;
};
}  // namespace

TEST_CASE("announcements go to this thread's listener while it is installed") {
  Recorder outer, inner;
  hb::announce_build_stage("before");  // no listener: nothing happens
  {
    const hb::ScopedBuildProgressListener scope(&outer);
    hb::announce_cached_build("voxmap", true);
    {
      const hb::ScopedBuildProgressListener nested(&inner);
      hb::announce_cached_build("pointshell", false);
      hb::announce_build_progress(3, 8);
      // Another thread has no listener.
      std::thread([] { hb::announce_build_stage("elsewhere"); }).join();
    }
    hb::announce_build_stage("after the nested one");
  }
  hb::announce_build_stage("after");
  CHECK(outer.said == std::vector<std::string>{"voxmap: cache hit", "after the nested one"});
  CHECK(inner.said == std::vector<std::string>{"pointshell: building", "3/8"});
}
