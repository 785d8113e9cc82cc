// JSON pointers (RFC 6901) into a scenario document: split into tokens,
// and a value set at one, as sweeps and the stability searches edit a
// scenario before it is loaded.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace hb {

/// The reference tokens of a JSON pointer, unescaped ("/a~1b/0" -> {"a/b",
/// "0"}); nullopt when the text is not a pointer ("" or not starting with
/// '/', or a '~' not followed by 0 or 1).
std::optional<std::vector<std::string>> json_pointer_tokens(const std::string& pointer);

/// Sets `value` in `document` at the JSON pointer whose tokens are given
/// (json_pointer_tokens). Every component but the last must exist, except
/// a section whose keys have documented defaults (/coupling, /device,
/// /reference, /trace/params, /algorithms/i/params), which is created
/// empty; the last may be a new key of an existing object (a parameter the
/// scenario leaves at its default) but not a new array element. Returns
/// why not, or nullopt when set.
std::optional<std::string> set_at_pointer(nlohmann::ordered_json& document,
                                          const std::vector<std::string>& tokens,
                                          const nlohmann::ordered_json& value);

}  // namespace hb
