#include "harness/scenario/json_pointer.h"

#include "harness/scenario/json_fields.h"

namespace hb {

using Json = nlohmann::ordered_json;

std::optional<std::vector<std::string>> json_pointer_tokens(const std::string& pointer) {
  if (pointer.empty() || pointer.front() != '/') return std::nullopt;
  std::vector<std::string> tokens;
  std::string token;
  for (std::size_t i = 1; i <= pointer.size(); ++i) {
    if (i == pointer.size() || pointer[i] == '/') {
      tokens.push_back(token);
      token.clear();
    } else if (pointer[i] == '~') {
      if (i + 1 >= pointer.size() || (pointer[i + 1] != '0' && pointer[i + 1] != '1'))
        return std::nullopt;
      token += pointer[i + 1] == '0' ? '~' : '/';
      ++i;
    } else {
      token += pointer[i];
    }
  }
  return tokens;
}

namespace {

std::string json_type_word(const Json& value) {
  if (value.is_object()) return "an object";
  if (value.is_array()) return "an array";
  if (value.is_string()) return "a string";
  if (value.is_boolean()) return "a boolean";
  if (value.is_null()) return "null";
  return "a number";
}

std::optional<std::size_t> array_index(const std::string& token) {
  if (token.empty() || token.size() > 9) return std::nullopt;
  if (token.size() > 1 && token.front() == '0') return std::nullopt;
  std::size_t index = 0;
  for (char c : token) {
    if (c < '0' || c > '9') return std::nullopt;
    index = index * 10 + static_cast<std::size_t>(c - '0');
  }
  return index;
}

/// Sections a scenario may omit, their keys then taking documented
/// defaults (docs/scenario-format.md); "*" stands for an array index.
const std::vector<std::vector<std::string>> kDefaultedSections = {
    {"coupling"}, {"device"}, {"reference"}, {"trace", "params"}, {"algorithms", "*", "params"}};

/// Whether tokens[0..last] name a defaulted section.
bool is_defaulted_section(const std::vector<std::string>& tokens, std::size_t last) {
  for (const auto& section : kDefaultedSections) {
    if (section.size() != last + 1) continue;
    bool match = true;
    for (std::size_t i = 0; i <= last && match; ++i)
      match = section[i] == tokens[i] || (section[i] == "*" && array_index(tokens[i]));
    if (match) return true;
  }
  return false;
}

std::string where(const std::string& pointer) {
  return pointer.empty() ? "the scenario's top level" : "\"" + pointer + "\"";
}

}  // namespace

std::optional<std::string> set_at_pointer(Json& document, const std::vector<std::string>& tokens,
                                          const Json& value) {
  Json* current = &document;
  std::string walked;
  for (std::size_t i = 0; i < tokens.size(); ++i) {
    const std::string& token = tokens[i];
    const bool last = i + 1 == tokens.size();
    if (current->is_object()) {
      if (!last && !current->contains(token)) {
        if (!is_defaulted_section(tokens, i))
          return where(walked) + " has no key \"" + token + "\"";
        (*current)[token] = Json::object();  // the section's other keys keep their defaults
      }
      current = &(*current)[token];
    } else if (current->is_array()) {
      const std::optional<std::size_t> index = array_index(token);
      if (!index) return where(walked) + " is an array; \"" + token + "\" is not an element index";
      if (*index >= current->size())
        return where(walked) + " has " + std::to_string(current->size()) +
               " elements, no element " + token;
      current = &(*current)[*index];
    } else {
      return where(walked) + " is " + json_type_word(*current) + ", not an object or array";
    }
    walked += '/';
    walked += json_pointer_token(token);
  }
  *current = value;
  return std::nullopt;
}

}  // namespace hb
