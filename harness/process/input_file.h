// Input files are regular files: a FIFO given as an input would block the
// reader until someone writes to it, a device would be read forever.
#pragma once

#include <filesystem>
#include <fstream>
#include <iterator>
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

/// The bytes of an input file, after require_regular_file (what: "a
/// summary.json", ...); InputError at `path` when it cannot be read.
inline std::string read_regular_file(const std::filesystem::path& path, const std::string& what) {
  require_regular_file(path, what);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), "", "cannot open " + what);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw InputError(path.string(), "", "cannot read " + what);
  return bytes;
}

}  // namespace hb
