// The run folders a command is pointed at: a run folder, its summary.json,
// or a folder holding run folders at any depth (a suite, a sweep).
#pragma once

#include <filesystem>
#include <vector>

namespace hb {

/// Run folders (folders holding a summary.json) at or beneath `input`,
/// sorted. Throws InputError naming `input` when it is not a folder, cannot
/// be listed, or holds no summary.json.
std::vector<std::filesystem::path> find_run_folders(const std::filesystem::path& input);

}  // namespace hb
