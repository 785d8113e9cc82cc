// The run folders a command is pointed at: a run folder, its summary.json,
// or a folder holding run folders at any depth (a suite, a sweep).
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace hb {

/// Files called `name` at or beneath `input` (a folder, or such a file),
/// sorted; none is not an error. Throws InputError naming `input` when it is
/// neither, or cannot be listed.
std::vector<std::filesystem::path> find_files_named(const std::filesystem::path& input,
                                                    const std::string& name);

/// Run folders (folders holding a summary.json) at or beneath `input`,
/// sorted. Throws InputError naming `input` when it is not a folder, cannot
/// be listed, or holds no summary.json.
std::vector<std::filesystem::path> find_run_folders(const std::filesystem::path& input);

/// The run folders of every input, each folder once (by its canonical
/// path), in the order of the inputs.
std::vector<std::filesystem::path> find_run_folders(
    const std::vector<std::filesystem::path>& inputs);

/// A run folder's summary.json, read and checked for what readers of run
/// folders rely on: schema_version 1, scenario.name a string, runs an array
/// of objects with a string label and a timing object. Throws InputError
/// naming the file and the JSON pointer otherwise.
nlohmann::ordered_json read_run_summary(const std::filesystem::path& file);

}  // namespace hb
