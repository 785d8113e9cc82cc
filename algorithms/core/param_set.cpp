#include "hapticbench/param_set.h"

#include <cmath>
#include <limits>
#include <sstream>

#include "hapticbench/input_error.h"

namespace hb {

namespace {
std::string range_text(double min, double max) {
  std::ostringstream out;
  if (max == std::numeric_limits<double>::max())
    out << ">= " << min;  // no upper bound
  else
    out << "in [" << min << ", " << max << "]";
  return out.str();
}

std::string number_text(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

std::string list_text(const std::vector<double>& values) {
  std::string text = "[";
  for (std::size_t i = 0; i < values.size(); ++i) text += (i ? ", " : "") + number_text(values[i]);
  return text + "]";
}
}  // namespace

void ParamSet::declare(const std::string& key, std::string default_value,
                       std::string accepted) const {
  for (const ParamDeclaration& d : declared_)
    if (d.key == key) return;  // the first accessor asked says what it is
  declared_.push_back({key, std::move(default_value), std::move(accepted)});
}

double ParamSet::number(const std::string& key, double fallback, double min, double max) const {
  declare(key, number_text(fallback), "number " + range_text(min, max));
  read_.insert(key);
  auto it = values_.find(key);
  if (it == values_.end()) return fallback;
  const double* value = std::get_if<double>(&it->second);
  if (!value) throw InputError("", field(key), "expected a number " + range_text(min, max));
  if (!std::isfinite(*value) || *value < min || *value > max) {
    std::ostringstream got;
    got << *value;
    throw InputError("", field(key),
                     "expected a number " + range_text(min, max) + ", got " + got.str());
  }
  return *value;
}

long long ParamSet::integer(const std::string& key, long long fallback, long long min,
                            long long max) const {
  declare(key, std::to_string(fallback),
          "whole number " + range_text(static_cast<double>(min), static_cast<double>(max)));
  const double value = number(key, static_cast<double>(fallback), static_cast<double>(min),
                              static_cast<double>(max));
  if (value != std::floor(value))
    throw InputError("", field(key), "expected a whole number " + range_text(min, max));
  return static_cast<long long>(value);
}

std::string ParamSet::choice(const std::string& key, const std::string& fallback,
                             const std::vector<std::string>& allowed) const {
  std::string list;
  for (const auto& a : allowed) list += (list.empty() ? "\"" : ", \"") + a + "\"";
  declare(key, "\"" + fallback + "\"", "one of " + list);
  read_.insert(key);
  auto it = values_.find(key);
  if (it == values_.end()) return fallback;
  const std::string* value = std::get_if<std::string>(&it->second);
  if (!value) throw InputError("", field(key), "expected one of " + list);
  for (const auto& a : allowed)
    if (*value == a) return *value;
  throw InputError("", field(key), "expected one of " + list + ", got \"" + *value + "\"");
}

bool ParamSet::flag(const std::string& key, bool fallback) const {
  declare(key, fallback ? "true" : "false", "true or false");
  read_.insert(key);
  auto it = values_.find(key);
  if (it == values_.end()) return fallback;
  const bool* value = std::get_if<bool>(&it->second);
  if (!value) throw InputError("", field(key), "expected true or false");
  return *value;
}

std::vector<double> ParamSet::numbers(const std::string& key, const std::vector<double>& fallback,
                                      std::size_t size) const {
  declare(key, list_text(fallback), "list of " + std::to_string(size) + " numbers");
  read_.insert(key);
  auto it = values_.find(key);
  if (it == values_.end()) return fallback;
  const auto* value = std::get_if<std::vector<double>>(&it->second);
  const std::string expected = "expected a list of " + std::to_string(size) + " finite numbers";
  if (!value || value->size() != size) throw InputError("", field(key), expected);
  for (double x : *value)
    if (!std::isfinite(x)) throw InputError("", field(key), expected);
  return *value;
}

std::optional<long long> ParamSet::integer_or_word(const std::string& key, long long fallback,
                                                   long long min, long long max,
                                                   const std::string& word) const {
  declare(key, std::to_string(fallback),
          "whole number " + range_text(static_cast<double>(min), static_cast<double>(max)) +
              " or \"" + word + "\"");
  auto it = values_.find(key);
  if (it != values_.end()) {
    if (const std::string* text = std::get_if<std::string>(&it->second)) {
      read_.insert(key);
      if (*text == word) return std::nullopt;
      throw InputError("", field(key),
                       "expected a whole number " +
                           range_text(static_cast<double>(min), static_cast<double>(max)) +
                           " or \"" + word + "\", got \"" + *text + "\"");
    }
  }
  return integer(key, fallback, min, max);
}

void ParamSet::reject_unknown() const {
  for (const auto& [key, value] : values_) {
    if (!read_.count(key)) {
      std::string known;
      for (const auto& k : read_) known += (known.empty() ? "" : ", ") + k;
      throw InputError("", field(key), "unknown parameter (known: " + known + ")");
    }
  }
}

}  // namespace hb
