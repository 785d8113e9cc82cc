#include "algorithms/core/temporary_folder.h"

#include <cstdlib>
#include <string>
#include <system_error>

#include "hapticbench/input_error.h"

namespace hb {

std::filesystem::path temporary_folder() {
  std::error_code error;
  std::filesystem::path folder = std::filesystem::temp_directory_path(error);
  if (error) {
    const char* tmpdir = std::getenv("TMPDIR");
    throw InputError(tmpdir != nullptr ? tmpdir : "", "TMPDIR",
                     "expected a folder for temporary files (" + error.message() + ")");
  }
  return folder;
}

}  // namespace hb
