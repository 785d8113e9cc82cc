#include "harness/cli/run_folder_search.h"

#include <algorithm>
#include <fstream>
#include <set>
#include <sstream>
#include <system_error>

#include "hapticbench/input_error.h"
#include "harness/scenario/json_fields.h"

namespace hb {

namespace fs = std::filesystem;

std::vector<fs::path> find_files_named(const fs::path& input, const std::string& name) {
  std::error_code error;
  if (fs::is_regular_file(input, error) && input.filename() == name) return {input};
  if (!fs::is_directory(input, error))
    throw InputError(input.string(), "",
                     fs::exists(input, error)
                         ? "expected a run folder (with summary.json) or a folder of run folders"
                         : "no such folder");
  std::vector<fs::path> files;
  fs::recursive_directory_iterator it(input, fs::directory_options::skip_permission_denied, error);
  if (error) throw InputError(input.string(), "", "cannot list the folder: " + error.message());
  for (const fs::recursive_directory_iterator end; it != end; it.increment(error)) {
    if (error) throw InputError(input.string(), "", "cannot list the folder: " + error.message());
    if (it->path().filename() == name && it->is_regular_file(error)) files.push_back(it->path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::vector<fs::path> find_run_folders(const fs::path& input) {
  std::vector<fs::path> folders;
  for (const fs::path& summary : find_files_named(input, "summary.json"))
    folders.push_back(summary.parent_path().empty() ? fs::path(".") : summary.parent_path());
  if (folders.empty())
    throw InputError(input.string(), "",
                     "no summary.json in this folder or beneath it (expected a run folder or a "
                     "folder of run folders)");
  std::sort(folders.begin(), folders.end());
  return folders;
}

std::vector<fs::path> find_run_folders(const std::vector<fs::path>& inputs) {
  std::vector<fs::path> folders;
  std::set<fs::path> seen;
  for (const fs::path& input : inputs) {
    for (const fs::path& folder : find_run_folders(input)) {
      std::error_code error;
      const fs::path key = fs::weakly_canonical(folder, error);
      if (seen.insert(error ? folder : key).second) folders.push_back(folder);
    }
  }
  return folders;
}

nlohmann::ordered_json read_run_summary(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string(), "", "cannot read the file");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw InputError(file.string(), "", "cannot read the file");
  nlohmann::ordered_json summary = parse_json_document(text.str(), file.string());
  const JsonField root(summary, file.string(), "");
  root.require_object("expected a summary object");
  if (!root.has("schema_version"))
    throw InputError(file.string(), "/schema_version", "missing; expected 1");
  const JsonField version = root.existing_member("schema_version");
  if (!version.json().is_number_integer() || version.json().get<int64_t>() != 1)
    version.fail("expected schema version 1 (the version this hapticbench reads)");
  const JsonField scenario = root.member("scenario", "expected the scenario");
  scenario.require_object("expected an object");
  scenario.member("name", "expected the scenario's name").string("expected a string");
  const JsonField runs = root.member("runs", "expected an array of runs");
  const std::size_t count = runs.array_size("expected an array of runs");
  for (std::size_t i = 0; i < count; ++i) {
    const JsonField run = runs.element(i);
    run.require_object("expected a run object");
    run.member("label", "expected the run's label").string("expected the run's label");
    run.member("timing", "expected the run's timing").require_object("expected an object");
    // The renderer opens these beside the summary: names inside the folder.
    for (const char* name : {"ticks_file", "schedule_file"})
      if (run.has(name) && !run.existing_member(name).json().is_null())
        run.existing_member(name).file_name_inside("expected a file name");
  }
  return summary;
}

}  // namespace hb
