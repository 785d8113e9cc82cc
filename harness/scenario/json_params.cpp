#include "harness/scenario/json_params.h"

#include "hapticbench/input_error.h"
#include "harness/scenario/json_fields.h"

namespace hb {

namespace {

template <typename Json>
std::string preview(const Json& value) {
  return json_value_preview(nlohmann::ordered_json(value));
}

template <typename Json>
ParamSet convert(const Json& params, const std::string& prefix, const std::string& source) {
  if (!params.is_object())
    throw InputError(source, prefix, "expected an object of parameters, got " + preview(params));
  ParamSet set(prefix);
  for (const auto& item : params.items()) {
    const Json& value = item.value();
    const std::string field = prefix + "/" + json_pointer_token(item.key());
    const std::string expected =
        "expected a number, a string, true/false or a list of numbers, got " + preview(value);
    if (value.is_boolean()) {
      set.set(item.key(), value.template get<bool>());
    } else if (value.is_number()) {
      set.set(item.key(), value.template get<double>());
    } else if (value.is_string()) {
      set.set(item.key(), value.template get<std::string>());
    } else if (value.is_array()) {
      std::vector<double> numbers;
      for (const Json& element : value) {
        if (!element.is_number()) throw InputError(source, field, expected);
        numbers.push_back(element.template get<double>());
      }
      set.set(item.key(), std::move(numbers));
    } else {
      throw InputError(source, field, expected);
    }
  }
  return set;
}

}  // namespace

ParamSet param_set_from_json(const nlohmann::json& params, const std::string& prefix,
                             const std::string& source) {
  return convert(params, prefix, source);
}

ParamSet param_set_from_json(const nlohmann::ordered_json& params, const std::string& prefix,
                             const std::string& source) {
  return convert(params, prefix, source);
}

}  // namespace hb
