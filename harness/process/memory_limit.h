// The memory ceiling the command line tool puts on itself: an input that
// would need more memory than the ceiling (a corrupt count in a file, say)
// ends in exit 2 with "needs more than N MB", never in the kernel's
// out-of-memory killer taking the process (or a neighbour) without a word.
#pragma once

#include <cstdint>
#include <string>

namespace hb {

/// The default ceiling (MB): half of the machine's physical memory.
std::uint64_t default_memory_limit_mb();

/// Limits this process's address space (RLIMIT_AS, soft limit) to `mb`
/// MB. Returns false, changing nothing, in builds with AddressSanitizer
/// (its shadow memory reserves terabytes of address space) and when the
/// hard limit is lower.
bool apply_memory_limit(std::uint64_t mb);

/// The ceiling applied by apply_memory_limit, in MB (0: none).
std::uint64_t applied_memory_limit_mb();

/// What to tell the user when an allocation failed under the ceiling.
std::string memory_limit_message();

}  // namespace hb
