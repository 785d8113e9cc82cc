// The folder for temporary files: TMPDIR, else /tmp.
#pragma once

#include <filesystem>

namespace hb {

/// The temporary folder. Throws InputError naming TMPDIR and its value
/// when it is not a folder (TMPDIR=/no/such), instead of a message with an
/// empty path.
std::filesystem::path temporary_folder();

}  // namespace hb
