#include "harness/output/run_folder.h"

#include <fcntl.h>
#include <unistd.h>

#include <fstream>
#include <stdexcept>
#include <string_view>
#include <system_error>
#include <vector>

#include "algorithms/core/replacing_file.h"
#include "hapticbench/input_error.h"
#include "harness/output/output_ownership.h"
#include "harness/process/liveness_lock.h"

namespace hb {

namespace fs = std::filesystem;

namespace {

// Throws std::filesystem::filesystem_error with the path and the cause.
void write_whole_file(const fs::path& path, const std::string& content) {
  write_file_replacing(path, content);
}

/// A new folder beside `destination` for this process:
/// <name><suffix><pid>, or <name><suffix><pid>-<n> when a folder of that
/// name is held by another live process (the same id in another PID
/// namespace). One of hapticbench's whose lock nobody holds is removed
/// first; anything else in the way is refused.
fs::path new_sibling_of_ours(const fs::path& destination, const std::string& suffix) {
  const std::string base = destination.filename().string() + suffix + std::to_string(::getpid());
  for (int attempt = 0;; ++attempt) {
    fs::path path = destination;
    path.replace_filename(attempt == 0 ? base : base + "-" + std::to_string(attempt));
    std::error_code error;
    if (fs::symlink_status(path, error).type() == fs::file_type::not_found) return path;
    if (!is_owned_folder(path))
      throw InputError(path.string(), "",
                       "is in the way of hapticbench's staging folder and was not written by "
                       "hapticbench; remove it yourself");
    if (remove_if_abandoned(path, [](const fs::path& folder) { fs::remove_all(folder); }))
      return path;
  }
}

// Copies `source` to `destination` in blocks through a TemporarySibling, so
// that an error names its real cause (a full disk is "No space left on
// device", not the "Input/output error" of the library's copy).
void copy_through_temporary(const fs::path& source, const fs::path& destination) {
  const int in = ::open(source.c_str(), O_RDONLY | O_CLOEXEC);
  if (in < 0)
    throw fs::filesystem_error("cannot read a finished file", source,
                               std::error_code(errno, std::generic_category()));
  TemporarySibling out(destination);
  std::vector<char> block(1 << 20);
  for (;;) {
    const ssize_t got = ::read(in, block.data(), block.size());
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) {
      const int cause = errno;
      ::close(in);
      throw fs::filesystem_error("cannot read a finished file", source,
                                 std::error_code(cause, std::generic_category()));
    }
    if (got == 0) break;
    try {
      out.write(std::string_view(block.data(), static_cast<std::size_t>(got)));
    } catch (...) {
      ::close(in);
      throw;
    }
  }
  ::close(in);
  out.commit();
}

}  // namespace

bool is_staging_sibling(const std::string& file, const std::string& name) {
  for (const char* suffix : {".partial-", ".old-"}) {
    const std::string prefix = name + suffix;
    if (file.size() <= prefix.size() || file.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string rest = file.substr(prefix.size());
    const std::size_t dash = rest.find('-');
    const auto digits = [](const std::string& text) {
      return !text.empty() && text.size() <= 10 &&
             text.find_first_not_of("0123456789") == std::string::npos;
    };
    if (dash == std::string::npos ? digits(rest)
                                  : digits(rest.substr(0, dash)) && digits(rest.substr(dash + 1)))
      return true;
  }
  return false;
}

void remove_abandoned_staging(const fs::path& path) {
  if (!is_owned_folder(path)) return;
  remove_if_abandoned(path, [](const fs::path& folder) {
    std::error_code ignored;
    fs::remove_all(folder, ignored);
  });
}

namespace {

// Staging and set-aside folders beside `destination` (<name>.partial-<pid>,
// <name>.old-<pid>) that a process no longer running left behind (killed
// before it could clean up) and that carry hapticbench's marker.
void remove_stale_siblings(const fs::path& destination) {
  const fs::path parent = destination.has_parent_path() ? destination.parent_path() : ".";
  const std::string name = destination.filename().string();
  std::error_code error;
  std::vector<fs::path> stale;
  for (const auto& entry : fs::directory_iterator(parent, error))
    if (is_staging_sibling(entry.path().filename().string(), name)) stale.push_back(entry.path());
  for (const fs::path& path : stale) remove_abandoned_staging(path);
}

}  // namespace

StagedRunFolder::StagedRunFolder(fs::path destination, OutputFolderKind kind, bool remove_stale)
    : destination_(std::move(destination)), kind_(kind) {
  require_replaceable_folder(destination_, kind_);
  if (remove_stale) remove_stale_siblings(destination_);
  staging_ = new_sibling_of_ours(destination_, ".partial-");
  if (staging_.has_parent_path()) fs::create_directories(staging_.parent_path());
  fs::create_directory(staging_);
  try {
    // Locked before it is marked: a folder marked ours and unlocked is
    // one its process left.
    lock_ = std::make_unique<LivenessLock>(staging_);
    write_whole_file(staging_ / kOwnershipMarkerName, ownership_marker_text(kind_, {}));
  } catch (...) {
    // The destructor does not run for a constructor that throws.
    std::error_code ignored;
    fs::remove_all(staging_, ignored);
    throw;
  }
}

StagedRunFolder::~StagedRunFolder() {
  if (!committed_) {
    std::error_code ignored;
    fs::remove_all(staging_, ignored);
  }
}

void StagedRunFolder::list_file(const std::string& name) {
  // Listed first, so that a staging folder left by a killed process is
  // still recognised as ours and can be cleaned up.
  files_.push_back(name);
  write_whole_file(staging_ / kOwnershipMarkerName, ownership_marker_text(kind_, files_));
}

void StagedRunFolder::write_file(const std::string& name, const std::string& content) {
  list_file(name);
  write_whole_file(staging_ / name, content);
}

void StagedRunFolder::move_file(const std::string& name, const fs::path& source) {
  list_file(name);
  std::error_code error;
  fs::rename(source, staging_ / name, error);
  if (error == std::errc::cross_device_link) {
    copy_through_temporary(source, staging_ / name);
    fs::remove(source);
  } else if (error) {
    throw fs::filesystem_error("cannot move a finished file into the run folder", source,
                               staging_ / name, error);
  }
}

bool StagedRunFolder::commit() {
  // Checked again: the destination may have changed while the run ran.
  const bool owned = require_replaceable_folder(destination_, kind_);
  const bool had_old = owned || fs::exists(destination_);
  // The old folder is moved aside first, so the destination is always
  // either the complete old folder or the complete new one.
  // The old folder is locked before it is set aside, so that a kill between
  // the renames leaves it recognisably abandoned.
  std::unique_ptr<LivenessLock> old_lock =
      owned ? std::make_unique<LivenessLock>(destination_) : nullptr;
  const fs::path old = had_old ? new_sibling_of_ours(destination_, ".old-") : fs::path();
  if (had_old) fs::rename(destination_, old);
  fs::rename(staging_, destination_);
  committed_ = true;
  lock_->release_and_remove(destination_);
  if (had_old) fs::remove_all(old);
  return owned;
}

}  // namespace hb
