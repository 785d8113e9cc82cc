// Where on-disk caches of built structures (voxmaps, pointshells, convex
// hierarchies) live.
#pragma once

#include <filesystem>
#include <optional>

namespace hb {

/// The cache folder: $HAPTICBENCH_CACHE_DIR, else $XDG_CACHE_HOME/hapticbench,
/// else $HOME/.cache/hapticbench; nullopt when none of them is set (an empty
/// variable counts as unset). The folder may not exist yet.
std::optional<std::filesystem::path> default_cache_directory();

}  // namespace hb
