// Typed reads of one JSON value that know where the value is (file and
// JSON pointer), so every rejection says where it happened, what was
// expected and what was found: "x.json: /tool/density: expected a positive
// number (kg/m³), got -3". Harness only (nlohmann-json).
#pragma once

#include <cstdint>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "hapticbench/pose.h"

namespace hb {

/// A JSON value, the file it came from and its JSON pointer (RFC 6901).
/// Holds a reference: the document must outlive it.
class JsonField {
 public:
  JsonField(const nlohmann::ordered_json& value, std::string source, std::string pointer)
      : value_(&value), source_(std::move(source)), pointer_(std::move(pointer)) {}

  const nlohmann::ordered_json& json() const { return *value_; }
  const std::string& source() const { return source_; }
  /// "" for the document root.
  const std::string& pointer() const { return pointer_; }

  /// Throws InputError(source, pointer, expected + ", got <value>").
  [[noreturn]] void fail(const std::string& expected) const;
  /// Throws InputError(source, pointer, message) with the message as given.
  [[noreturn]] void fail_with(const std::string& message) const;

  // Objects.
  /// Fails unless the value is an object.
  void require_object(const std::string& expected) const;
  /// Fails naming every key of this object that is not in `known`, with a
  /// "did you mean" for a near miss. noun: what a key is here ("key",
  /// "budget").
  void reject_unknown_keys(const std::vector<std::string_view>& known,
                           std::string_view noun = "key") const;
  bool has(const std::string& key) const;
  /// The member, failing "missing; expected ..." when absent.
  JsonField member(const std::string& key, const std::string& expected) const;
  /// The member; only call after has(key).
  JsonField existing_member(const std::string& key) const;

  // Arrays.
  /// Number of elements; fails unless the value is an array.
  std::size_t array_size(const std::string& expected) const;
  JsonField element(std::size_t index) const;

  // Scalars.
  /// A finite number.
  double number(const std::string& expected) const;
  /// A number > 0 (and finite).
  double positive_number(const std::string& expected) const;
  /// A number >= 0 (and finite).
  double non_negative_number(const std::string& expected) const;
  /// A whole number in [min, max] (JSON integer or a float with no fraction).
  int64_t integer(int64_t min, int64_t max, const std::string& expected) const;
  std::string string(const std::string& expected) const;
  /// A string naming a file inside the folder it was read from: no '/', not
  /// "." or "..", not empty (a summary's ticks_file: "../../etc/passwd"
  /// must not be opened).
  std::string file_name_inside(const std::string& expected) const;
  bool boolean(const std::string& expected) const;
  /// A string equal to one of `allowed`.
  std::string choice(std::initializer_list<std::string_view> allowed) const;
  std::string choice(const std::vector<std::string_view>& allowed) const;
  /// An array of exactly n finite numbers.
  std::vector<double> numbers(std::size_t n, const std::string& expected) const;
  Vec3 vec3(const std::string& expected) const;

 private:
  const nlohmann::ordered_json* value_;
  std::string source_;
  std::string pointer_;
};

/// Deepest nesting of arrays and objects a JSON input may have.
inline constexpr std::size_t kMaxJsonDepth = 64;

/// Escapes one JSON pointer reference token ("~" -> "~0", "/" -> "~1").
std::string json_pointer_token(std::string_view key);

/// A short rendering of a value for "got ..." in messages (compact JSON,
/// cut to about 60 characters).
std::string json_value_preview(const nlohmann::ordered_json& value);

/// Parses a JSON document. Malformed text throws InputError(source,
/// "line L, column C", parser message); an object with a repeated key throws
/// InputError(source, pointer of the key, ...), since the parser would keep
/// only one of the values silently. Nesting deeper than kMaxJsonDepth and
/// numbers beyond a double's range throw InputError with their position.
/// Comments (// to the end of the line, /* ... */) are skipped.
nlohmann::ordered_json parse_json_document(const std::string& text, const std::string& source);

}  // namespace hb
