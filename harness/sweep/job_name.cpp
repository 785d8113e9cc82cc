#include "harness/sweep/job_name.h"

#include "harness/scenario/json_pointer.h"
#include "harness/sweep/sweep_spec.h"

namespace hb {

namespace {

constexpr std::size_t kMaxFolderNameChars = 255;

bool is_safe_char(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
         c == '.' || c == '-' || c == '=';
}

// Keeps safe characters, drops the punctuation of JSON syntax and turns the
// rest into '_' (so "a/b" stays two words).
std::string folder_safe_text(const std::string& text) {
  std::string safe;
  for (char c : text) {
    if (is_safe_char(c))
      safe += c;
    else if (c == '[' || c == ']' || c == '{' || c == '}' || c == '"' || c == ' ' || c == '+')
      continue;
    else
      safe += '_';
  }
  return safe;
}

}  // namespace

bool is_safe_folder_name(const std::string& name) {
  if (name.empty() || name == "." || name == ".." || name.size() > kMaxFolderNameChars)
    return false;
  for (char c : name)
    if (!is_safe_char(c)) return false;
  return true;
}

std::string grid_value_name_text(const nlohmann::ordered_json& value) {
  return folder_safe_text(value.is_string() ? value.get<std::string>() : value.dump());
}

std::string sweep_job_name(
    const std::string& scenario_name,
    const std::vector<std::pair<std::string, nlohmann::ordered_json>>& grid_values) {
  std::string name = folder_safe_text(scenario_name);
  for (const auto& [pointer, value] : grid_values) {
    const auto tokens = json_pointer_tokens(pointer);
    const std::string key = tokens && !tokens->empty() ? tokens->back() : pointer;
    name += "__" + folder_safe_text(key) + "=" + grid_value_name_text(value);
  }
  return name;
}

}  // namespace hb
