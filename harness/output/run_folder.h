// A run folder written all or nothing: files go into a staging folder
// beside the destination, which replaces the destination only on commit().
#pragma once

#include <filesystem>
#include <string>

namespace hb {

class StagedRunFolder {
 public:
  /// Creates `<destination>.partial-<pid>` (parents created as needed).
  explicit StagedRunFolder(std::filesystem::path destination);
  /// Removes the staging folder unless commit() succeeded.
  ~StagedRunFolder();
  StagedRunFolder(const StagedRunFolder&) = delete;
  StagedRunFolder& operator=(const StagedRunFolder&) = delete;

  /// Writes one file into the staging folder.
  void write_file(const std::string& name, const std::string& content) const;
  /// Replaces the destination with the staged folder.
  void commit();
  const std::filesystem::path& destination() const { return destination_; }

 private:
  std::filesystem::path destination_;
  std::filesystem::path staging_;
  bool committed_ = false;
};

}  // namespace hb
