// Conversion of a JSON "params" object into the plain ParamSet algorithms
// and generators read, so that they never see JSON. Harness only.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "hapticbench/param_set.h"

namespace hb {

/// Converts a JSON object of parameters: number -> double, string -> string,
/// true/false -> bool, array of numbers -> vector<double>. Anything else
/// (null, nested object, mixed array), or a value that is not an object,
/// throws InputError(source, "<prefix>/<key>", ...). prefix is the JSON
/// pointer of the object, e.g. "/algorithms/0/params"; the ParamSet keeps it
/// so that later range errors name the same field.
ParamSet param_set_from_json(const nlohmann::json& params, const std::string& prefix,
                             const std::string& source);
/// The same for a document parsed with key order kept.
ParamSet param_set_from_json(const nlohmann::ordered_json& params, const std::string& prefix,
                             const std::string& source);

}  // namespace hb
