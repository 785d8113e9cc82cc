// A shared library whose constructor leaves a mark: the file named by
// HAPTICBENCH_TEST_MARK is created when the library is loaded, before any
// entry point is called. A scenario or sweep that names it must not make
// hapticbench load it unless the user allowed that.
#include <fcntl.h>
#include <unistd.h>

#include <cstdlib>

namespace {

__attribute__((constructor)) void leave_mark() {
  const char* mark = std::getenv("HAPTICBENCH_TEST_MARK");
  if (mark == nullptr) return;
  const int fd = ::open(mark, O_WRONLY | O_CREAT | O_APPEND, 0644);
  if (fd < 0) return;
  const char text[] = "loaded\n";
  if (::write(fd, text, sizeof text - 1) < 0) {
  }
  ::close(fd);
}

}  // namespace

extern "C" __attribute__((visibility("default"))) int leaves_a_mark() { return 1; }
