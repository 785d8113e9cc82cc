// Input files are regular files: a FIFO given as an input would block the
// reader until someone writes to it, a device would be read forever.
#pragma once

#include <filesystem>
#include <string>
#include <system_error>

#include "hapticbench/input_error.h"

namespace hb {

/// Throws InputError at `path` unless it names a regular file (symlinks
/// followed): "file not found", or "is not a regular file ...; expected
/// <what>".
inline void require_regular_file(const std::filesystem::path& path, const std::string& what) {
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(path, error);
  if (status.type() == std::filesystem::file_type::not_found)
    throw InputError(path.string(), "", "file not found");
  if (status.type() != std::filesystem::file_type::regular)
    throw InputError(path.string(), "",
                     "is not a regular file (a folder, FIFO or device); expected " + what);
}

}  // namespace hb
