// What hapticbench may replace when it writes an output: only what it wrote
// itself. Every folder it writes (run folders, comparison folders, the
// staging folders beside them) carries an ownership marker listing the files
// it put there; a later command replaces such a folder only while it holds
// nothing else. Anything else at an output path (a folder of the user's, a
// regular file, a symlink, a device, a FIFO, a socket) is refused with an
// InputError naming the path before any work is done.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace hb {

/// Name of the marker file inside every folder hapticbench writes.
inline constexpr const char* kOwnershipMarkerName = ".hapticbench-output";

/// The kinds of folder hapticbench writes; one never replaces another kind.
enum class OutputFolderKind {
  kRun,         ///< a scenario's run folder (`run`, `sweep`)
  kComparison,  ///< `compare --out`
};

/// "run folder", "comparison folder".
const char* output_folder_kind_name(OutputFolderKind kind);

/// The marker's content: who wrote the folder, its kind and which files it
/// holds.
std::string ownership_marker_text(OutputFolderKind kind, const std::vector<std::string>& files);

/// Whether `folder` is a folder (not a symlink to one) that hapticbench
/// wrote: its marker is readable and every entry in it is listed there.
/// With `kind`, the marker must also name that kind.
bool is_owned_folder(const std::filesystem::path& folder,
                     std::optional<OutputFolderKind> kind = std::nullopt);

/// Throws InputError(destination, "", why) unless a folder hapticbench
/// writes may take the place of `destination`: nothing is there, an empty
/// folder is there, or a folder of `kind` hapticbench wrote
/// (is_owned_folder). Returns true when something of hapticbench's is there
/// (it will be replaced), false when nothing or an empty folder is.
bool require_replaceable_folder(const std::filesystem::path& destination, OutputFolderKind kind);

/// Throws InputError(destination, "", why) unless a file hapticbench writes
/// may take the place of `destination`: nothing is there, or a regular file
/// (not a symlink) that `written_by_hapticbench` recognises. `what` names
/// the kind of file in the message, e.g. "report".
void require_replaceable_file(
    const std::filesystem::path& destination, const std::string& what,
    const std::function<bool(const std::filesystem::path&)>& written_by_hapticbench);

/// Creates `folder` (and its parents) when missing, for outputs that go
/// inside it (several run folders, a sweep's job folders); an existing
/// folder, or a symlink to one, is used as it is. Throws InputError naming
/// the path and the reason when it is something else or cannot be created.
void create_output_container(const std::filesystem::path& folder);

}  // namespace hb
