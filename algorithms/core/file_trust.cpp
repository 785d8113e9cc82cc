#include "algorithms/core/file_trust.h"

#include <sys/stat.h>
#include <unistd.h>

#include <system_error>

namespace hb {

namespace fs = std::filesystem;

std::string writable_by_others(const fs::path& path) {
  std::error_code error;
  const fs::path real = fs::canonical(path, error);
  if (error) return path.string() + " cannot be resolved (" + error.message() + ")";
  const uid_t user = ::geteuid();
  bool leaf = true;
  for (fs::path at = real;; at = at.parent_path()) {
    struct stat status {};
    if (::lstat(at.c_str(), &status) != 0) return at.string() + " cannot be examined";
    if (status.st_uid != user && status.st_uid != 0)
      return at.string() + " is owned by user " + std::to_string(status.st_uid);
    const bool sticky_folder = S_ISDIR(status.st_mode) && (status.st_mode & S_ISVTX) != 0;
    // A sticky folder above the path protects what is ours inside it; the
    // path itself must not be writable by others at all.
    if (!(sticky_folder && !leaf)) {
      if (status.st_mode & S_IWOTH) return at.string() + " is writable by every user";
      // A group of the user's own (Debian gives each user a private one).
      if ((status.st_mode & S_IWGRP) && status.st_gid != ::getegid())
        return at.string() + " is writable by its group";
    }
    leaf = false;
    if (at == at.root_path() || at.parent_path() == at) break;
  }
  return "";
}

}  // namespace hb
