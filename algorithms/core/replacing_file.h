// Files written whole or not at all, through a temporary file that cannot
// be anything of the user's: a reader of the destination sees the old file
// or the new one, never half of one, and no other path is touched.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

namespace hb {

/// A new file beside `destination`, named ".<name>.tmp-XXXXXX" (a unique
/// suffix; <name> cut short where the whole would pass 255 bytes) and
/// created exclusively (mkstemp: O_CREAT | O_EXCL, so it is
/// never a file, a symlink or anything else that was there before). Removed
/// when destroyed unless committed.
class TemporarySibling {
 public:
  /// Throws std::filesystem::filesystem_error naming the destination and
  /// the cause when it cannot be created.
  explicit TemporarySibling(std::filesystem::path destination);
  ~TemporarySibling();
  TemporarySibling(const TemporarySibling&) = delete;
  TemporarySibling& operator=(const TemporarySibling&) = delete;

  /// Appends the bytes. Throws std::filesystem::filesystem_error with the
  /// temporary file's path and the cause (its code: "No space left on
  /// device", ...).
  void write(std::string_view bytes);
  /// Closes the file and renames it over the destination. Throws as write()
  /// does, naming the destination.
  void commit();

  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path destination_;
  std::filesystem::path path_;
  int fd_ = -1;
  bool committed_ = false;
};

/// Writes `bytes` to `destination` through a TemporarySibling: the whole
/// file or, after a throw (std::filesystem::filesystem_error with the path
/// and the cause), nothing at all.
void write_file_replacing(const std::filesystem::path& destination, std::string_view bytes);

}  // namespace hb
