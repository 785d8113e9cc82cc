// A sweep job's name, which is also its run folder's name:
// "<scenario name>__<key>=<value>__...", one pair per grid key, where key
// is the last component of the grid key's JSON pointer.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

namespace hb {

/// True when `name` can be a folder name on any common file system (and a
/// scenario name): letters, digits, '_', '.', '-' and '=', not "." or "..",
/// at most 255 characters.
bool is_safe_folder_name(const std::string& name);

/// A grid value as it appears in a job name: a string as is, anything else
/// as compact JSON (3000, 0.5, true, [0.01,0,0]); brackets, braces, quotes,
/// spaces and '+' dropped, any other unsafe character turned into '_'.
std::string grid_value_name_text(const nlohmann::ordered_json& value);

/// "<scenario_name>__<key>=<value>__..." for (pointer, value) pairs in grid
/// order; characters a folder name cannot hold become '_'.
std::string sweep_job_name(
    const std::string& scenario_name,
    const std::vector<std::pair<std::string, nlohmann::ordered_json>>& grid_values);

}  // namespace hb
