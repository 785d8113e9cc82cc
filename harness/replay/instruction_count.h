// Instruction counts of the calls the replay loop measures, from valgrind's
// callgrind: a cost figure that does not depend on how busy the machine is.
// The harness re-runs itself under callgrind with collection off; the replay
// loop switches collection on around the measured calls only, and each
// measured pass ends with a dump whose total is the count. Without valgrind
// the client requests are a few no-op instructions.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>

namespace hb {

/// True when this process runs under valgrind.
bool running_on_valgrind();
/// Under callgrind: switches the collection of events on or off.
void toggle_instruction_collection();
/// Under callgrind: starts instrumenting (callgrind runs with
/// --instr-atstart=no, so that loading and preprocessing run fast).
void start_instrumentation();
/// Under callgrind: writes the events collected since the last dump into a
/// dump whose description is `tag`, and zeroes them.
void dump_instruction_counts(const std::string& tag);

/// The totals of every callgrind dump in `folder`, by the tag given to
/// dump_instruction_counts. Throws std::runtime_error for a dump without
/// a total.
std::map<std::string, int64_t> read_callgrind_dumps(const std::filesystem::path& folder);

}  // namespace hb
