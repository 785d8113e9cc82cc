// Adding context to an InputError raised by code that knew only part of the
// story: a ParamSet knows the field but not the file; a mesh reader knows
// the mesh file but not which scenario entry named it.
#pragma once

#include <string>

#include "hapticbench/input_error.h"

namespace hb {

/// The message of an InputError without its "source: location: " prefix.
inline std::string input_error_message(const InputError& error) {
  std::size_t prefix = 0;
  if (!error.source().empty()) prefix += error.source().size() + 2;
  if (!error.location().empty()) prefix += error.location().size() + 2;
  const std::string what = error.what();
  return prefix <= what.size() ? what.substr(prefix) : what;
}

/// The same error, with `source` filled in when it named no file.
inline InputError with_default_source(const InputError& error, const std::string& source) {
  if (!error.source().empty()) return error;
  return InputError(source, error.location(), input_error_message(error));
}

/// The same error with a note on where the file it names was referenced,
/// e.g. "(referenced by scenarios/x.json at /scene/0/mesh)".
inline InputError with_reference_note(const InputError& error, const std::string& referrer,
                                      const std::string& pointer) {
  return InputError(
      error.source().empty() ? referrer : error.source(), error.location(),
      input_error_message(error) + " (referenced by " + referrer + " at " + pointer + ")");
}

}  // namespace hb
