// Whether a file or folder can be changed by someone other than the user
// running hapticbench (or root): code it runs (the report renderer) and data
// it trusts (the disk cache) must not be.
#pragma once

#include <filesystem>
#include <string>

namespace hb {

/// "" when nobody but this user and root can replace or change `path`
/// (symlinks resolved); otherwise why not, naming the path that allows it
/// ("/tmp/share is owned by user 1001", "/srv/cache is writable by its
/// group"). The path and every folder above it must belong to this user
/// or root and be writable by nobody else (a group write bit counts only
/// for a group other than the user's own), except a sticky folder above it
/// (as /tmp is: others cannot rename or remove what is not theirs in it).
std::string writable_by_others(const std::filesystem::path& path);

}  // namespace hb
