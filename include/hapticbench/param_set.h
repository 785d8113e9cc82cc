// Algorithm parameters as plain values, so algorithms never see JSON.
// The harness fills a ParamSet from a scenario's "params" object; each
// algorithm's Settings reads it, validates ranges and names the field on
// error. Keys that no setting reads are reported as unknown.
#pragma once

#include <map>
#include <optional>
#include <set>
#include <string>
#include <variant>
#include <vector>

namespace hb {

/// One parameter value: a number, a string, a flag, or a list of numbers.
using ParamValue = std::variant<double, std::string, bool, std::vector<double>>;

/// A parameter as an accessor asked for it: what `hapticbench list` prints
/// for a generator (and docs tables are generated from).
struct ParamDeclaration {
  std::string key;
  std::string default_value;  ///< the fallback, as text ("0.005", "[0, 0, 0.03]", "\"implicit\"")
  std::string accepted;       ///< what a value must be, e.g. "number in [0, 1]"
};

class ParamSet {
 public:
  ParamSet() = default;
  /// prefix: how errors name the fields, e.g. "/algorithms/0/params".
  explicit ParamSet(std::string prefix) : prefix_(std::move(prefix)) {}

  void set(const std::string& key, ParamValue value) { values_[key] = std::move(value); }
  bool has(const std::string& key) const { return values_.count(key) != 0; }
  const std::map<std::string, ParamValue>& values() const { return values_; }
  const std::string& prefix() const { return prefix_; }

  /// A number in [min, max]; the fallback when absent. Throws InputError
  /// naming the field when present but not a number or out of range.
  double number(const std::string& key, double fallback, double min, double max) const;
  /// A whole number in [min, max].
  long long integer(const std::string& key, long long fallback, long long min, long long max) const;
  /// One of the allowed strings.
  std::string choice(const std::string& key, const std::string& fallback,
                     const std::vector<std::string>& allowed) const;
  bool flag(const std::string& key, bool fallback) const;
  /// A list of exactly `size` finite numbers.
  std::vector<double> numbers(const std::string& key, const std::vector<double>& fallback,
                              std::size_t size) const;
  /// Either a whole number in [min, max] or the given word (e.g. "measured");
  /// returns nullopt for the word.
  std::optional<long long> integer_or_word(const std::string& key, long long fallback,
                                           long long min, long long max,
                                           const std::string& word) const;

  /// Throws InputError for the first key no accessor has read.
  void reject_unknown() const;
  /// The field name errors use for key.
  std::string field(const std::string& key) const { return prefix_ + "/" + key; }

  /// Every parameter the accessors were asked for, in the order first asked.
  const std::vector<ParamDeclaration>& declared() const { return declared_; }

 private:
  std::string prefix_;
  std::map<std::string, ParamValue> values_;
  mutable std::set<std::string> read_;
  mutable std::vector<ParamDeclaration> declared_;
  void declare(const std::string& key, std::string default_value, std::string accepted) const;
};

}  // namespace hb
