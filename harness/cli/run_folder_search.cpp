#include "harness/cli/run_folder_search.h"

#include <algorithm>
#include <system_error>

#include "algorithms/core/input_error.h"

namespace hb {

namespace fs = std::filesystem;

std::vector<fs::path> find_run_folders(const fs::path& input) {
  std::error_code error;
  if (fs::is_regular_file(input, error) && input.filename() == "summary.json")
    return {input.parent_path().empty() ? fs::path(".") : input.parent_path()};
  if (!fs::is_directory(input, error))
    throw InputError(input.string(), "",
                     fs::exists(input, error)
                         ? "expected a run folder (with summary.json) or a folder of run folders"
                         : "no such folder");
  std::vector<fs::path> folders;
  fs::recursive_directory_iterator it(input, fs::directory_options::skip_permission_denied, error);
  if (error) throw InputError(input.string(), "", "cannot list the folder: " + error.message());
  for (const fs::recursive_directory_iterator end; it != end; it.increment(error)) {
    if (error) throw InputError(input.string(), "", "cannot list the folder: " + error.message());
    if (it->path().filename() == "summary.json" && it->is_regular_file(error))
      folders.push_back(it->path().parent_path());
  }
  if (folders.empty())
    throw InputError(input.string(), "",
                     "no summary.json in this folder or beneath it (expected a run folder or a "
                     "folder of run folders)");
  std::sort(folders.begin(), folders.end());
  return folders;
}

}  // namespace hb
