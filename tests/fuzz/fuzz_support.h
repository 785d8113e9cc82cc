// Fuzz targets' shared parts: each target feeds its bytes to one parser and
// lets only InputError through as an expected outcome; anything else (an
// exception of another type, a crash, a sanitizer report) is a finding.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "hapticbench/input_error.h"

namespace hb::fuzz {

inline std::string text_of(const uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

/// The bytes in a file of this process with the given name ending (parsers
/// that read paths: meshes by extension, traces, CCD query files).
inline std::filesystem::path file_of(const uint8_t* data, std::size_t size,
                                     const std::string& name) {
  const std::filesystem::path folder =
      std::filesystem::temp_directory_path() / ("hb_fuzz_" + std::to_string(::getpid()));
  std::filesystem::create_directories(folder);
  const std::filesystem::path path = folder / name;
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

/// Runs `parse`; an InputError is the parser refusing bad input, as it should.
template <class Parse>
int expect_input_errors_only(Parse&& parse) {
  try {
    parse();
  } catch (const InputError&) {
  }
  return 0;
}

}  // namespace hb::fuzz
