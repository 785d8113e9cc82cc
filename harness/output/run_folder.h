// A folder written all or nothing: files go into a staging folder beside
// the destination, which replaces the destination only on commit(). Both
// carry the ownership marker (output_ownership.h), and only an empty folder
// or one hapticbench wrote is ever replaced.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "harness/output/output_ownership.h"
#include "harness/process/liveness_lock.h"

namespace hb {

class StagedRunFolder {
 public:
  /// Checks that `destination` may be replaced (require_replaceable_folder;
  /// InputError if not), then creates `<destination>.partial-<pid>` with
  /// the marker and a lock held until commit or destruction (parents
  /// created as needed). With `remove_stale` it first removes the staging
  /// folders beside it whose lock no live process holds, which
  /// lists the parent folder: a sweep's jobs pass false, since the sweep
  /// cleans its folder once before they start (a scan per job of a
  /// 100,000-job folder would be quadratic).
  StagedRunFolder(std::filesystem::path destination, OutputFolderKind kind,
                  bool remove_stale = true);
  /// Removes the staging folder unless commit() succeeded.
  ~StagedRunFolder();
  StagedRunFolder(const StagedRunFolder&) = delete;
  StagedRunFolder& operator=(const StagedRunFolder&) = delete;

  /// Writes one file into the staging folder.
  void write_file(const std::string& name, const std::string& content);
  /// Moves a finished file into the staging folder under `name` (renamed,
  /// or copied and removed when it is on another filesystem).
  void move_file(const std::string& name, const std::filesystem::path& source);
  /// Replaces the destination with the staged folder. Returns true when an
  /// earlier folder of hapticbench's was replaced.
  bool commit();
  const std::filesystem::path& destination() const { return destination_; }

 private:
  void list_file(const std::string& name);

  std::filesystem::path destination_;
  std::filesystem::path staging_;
  OutputFolderKind kind_;
  std::vector<std::string> files_;
  std::unique_ptr<LivenessLock> lock_;
  bool committed_ = false;
};

/// Whether `file` is the name of a staging or set-aside folder of
/// `name`'s: <name>.partial-<pid>[-<n>] or <name>.old-<pid>[-<n>].
bool is_staging_sibling(const std::string& file, const std::string& name);

/// Removes `path`, a staging or set-aside folder, when it carries
/// hapticbench's marker and no live process holds its lock.
void remove_abandoned_staging(const std::filesystem::path& path);

}  // namespace hb
