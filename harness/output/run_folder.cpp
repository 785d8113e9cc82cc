#include "harness/output/run_folder.h"

#include <unistd.h>

#include <fstream>
#include <stdexcept>
#include <system_error>
#include <vector>

#include "algorithms/core/replacing_file.h"
#include "hapticbench/input_error.h"
#include "harness/output/output_ownership.h"
#include "harness/process/scratch_folder.h"

namespace hb {

namespace fs = std::filesystem;

namespace {

// Throws std::filesystem::filesystem_error with the path and the cause.
void write_whole_file(const fs::path& path, const std::string& content) {
  write_file_replacing(path, content);
}

/// A name beside `destination` for a folder of this process; one left by an
/// earlier process of the same id is removed only when it is ours.
fs::path sibling_of_ours(const fs::path& destination, const std::string& suffix) {
  fs::path path = destination;
  path += suffix + std::to_string(::getpid());
  std::error_code error;
  if (fs::symlink_status(path, error).type() != fs::file_type::not_found) {
    if (!is_owned_folder(path))
      throw InputError(path.string(), "",
                       "is in the way of hapticbench's staging folder and was not written by "
                       "hapticbench; remove it yourself");
    fs::remove_all(path);
  }
  return path;
}

// Staging and set-aside folders beside `destination` (<name>.partial-<pid>,
// <name>.old-<pid>) that a process no longer running left behind (killed
// before it could clean up) and that carry hapticbench's marker.
void remove_stale_siblings(const fs::path& destination) {
  const fs::path parent = destination.has_parent_path() ? destination.parent_path() : ".";
  const std::string name = destination.filename().string();
  std::error_code error;
  std::vector<fs::path> stale;
  for (const auto& entry : fs::directory_iterator(parent, error)) {
    const std::string file = entry.path().filename().string();
    for (const char* suffix : {".partial-", ".old-"}) {
      const std::string prefix = name + suffix;
      if (file.size() <= prefix.size() || file.compare(0, prefix.size(), prefix) != 0 ||
          file.size() - prefix.size() > 9 ||
          file.find_first_not_of("0123456789", prefix.size()) != std::string::npos)
        continue;
      if (process_is_gone(std::stol(file.substr(prefix.size())))) stale.push_back(entry.path());
    }
  }
  for (const fs::path& path : stale)
    if (is_owned_folder(path)) fs::remove_all(path, error);
}

}  // namespace

StagedRunFolder::StagedRunFolder(fs::path destination, OutputFolderKind kind, bool remove_stale)
    : destination_(std::move(destination)), kind_(kind) {
  require_replaceable_folder(destination_, kind_);
  if (remove_stale) remove_stale_siblings(destination_);
  staging_ = sibling_of_ours(destination_, ".partial-");
  if (staging_.has_parent_path()) fs::create_directories(staging_.parent_path());
  fs::create_directory(staging_);
  try {
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
    fs::copy_file(source, staging_ / name, fs::copy_options::overwrite_existing);
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
  const fs::path old = had_old ? sibling_of_ours(destination_, ".old-") : fs::path();
  if (had_old) fs::rename(destination_, old);
  fs::rename(staging_, destination_);
  committed_ = true;
  if (had_old) fs::remove_all(old);
  return owned;
}

}  // namespace hb
