// The memory ceiling the command line tool puts on itself: an input that
// would need more memory than the ceiling (a corrupt count in a file, say)
// ends in exit 2 with "needs more than N MB", never in the kernel's
// out-of-memory killer taking the process (or a neighbour) without a word.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

namespace hb {

/// The memory rule for reading input files (meshes, traces, scenarios,
/// sweeps, summaries; docs/limits.md, "Memory"): parsing n bytes takes at
/// most kInputMemoryPerByte · n bytes of heap plus kInputMemoryAllowance.
/// The densest cases are short text records that become fixed-size
/// structures: "0 0 0\n" (6 bytes) becomes a 24-byte point, a hash-map
/// entry and a merged vertex. The fuzz targets' replay checks every corpus
/// input against it (tests/fuzz/replay_main.cpp).
constexpr std::uint64_t kInputMemoryPerByte = 40;
constexpr std::uint64_t kInputMemoryAllowance = 16u << 20;

/// The default ceiling (MB): half of the machine's physical memory.
std::uint64_t default_memory_limit_mb();

/// Limits this process's address space (RLIMIT_AS, soft limit) to `mb`
/// MB beyond what it already maps when called (its code and libraries:
/// about 290 MB of address space before any input, which no input can
/// change; with the ceiling counted from zero, 256 MB ran nothing at all).
/// Returns false, changing nothing, in builds with AddressSanitizer (its
/// shadow memory reserves terabytes of address space) and when the hard
/// limit is lower.
bool apply_memory_limit(std::uint64_t mb);

/// Runs `reserve`, a library's start-up (Embree's device, which reserves
/// 128 MB for its allocator, and its threads' stacks and arenas), with the
/// ceiling lifted, then puts the ceiling back, raised by the address space
/// `reserve` left mapped: what a library reserves for itself is not the
/// input's to pay for. Without a ceiling it just runs `reserve`.
void outside_memory_limit(const std::function<void()>& reserve);

/// The ceiling applied by apply_memory_limit, in MB (0: none).
std::uint64_t applied_memory_limit_mb();

/// What to tell the user when an allocation failed under the ceiling.
std::string memory_limit_message();

}  // namespace hb
