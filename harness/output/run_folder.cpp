#include "harness/output/run_folder.h"

#include <unistd.h>

#include <fstream>
#include <stdexcept>
#include <system_error>

#include "algorithms/core/input_error.h"
#include "harness/output/output_ownership.h"

namespace hb {

namespace fs = std::filesystem;

namespace {

void write_whole_file(const fs::path& path, const std::string& content) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << content;
  out.close();
  if (!out) throw std::runtime_error("cannot write " + path.string());
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

}  // namespace

StagedRunFolder::StagedRunFolder(fs::path destination, OutputFolderKind kind)
    : destination_(std::move(destination)), kind_(kind) {
  require_replaceable_folder(destination_, kind_);
  staging_ = sibling_of_ours(destination_, ".partial-");
  if (staging_.has_parent_path()) fs::create_directories(staging_.parent_path());
  fs::create_directory(staging_);
  write_whole_file(staging_ / kOwnershipMarkerName, ownership_marker_text(kind_, {}));
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
