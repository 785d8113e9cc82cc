#include "harness/scenario/json_fields.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include "hapticbench/input_error.h"

namespace hb {

namespace {

using Json = nlohmann::ordered_json;

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

// Tracks where the parser is, so that a repeated key can be reported by its
// JSON pointer (the parser itself keeps one of the values without a word).
class DuplicateKeyFinder {
 public:
  bool on_event(nlohmann::json::parse_event_t event, const Json& parsed) {
    using Event = nlohmann::json::parse_event_t;
    switch (event) {
      case Event::object_start:
      case Event::array_start:
        frames_.push_back({event == Event::object_start, child_pointer(), {}, "", 0});
        break;
      case Event::key: {
        Frame& frame = frames_.back();
        frame.last_key = parsed.get<std::string>();
        if (!frame.keys.insert(frame.last_key).second && first_duplicate_.empty())
          first_duplicate_ = frame.pointer + "/" + json_pointer_token(frame.last_key);
        break;
      }
      case Event::value:
        finish_child();
        break;
      case Event::object_end:
      case Event::array_end:
        frames_.pop_back();
        finish_child();
        break;
    }
    return true;
  }
  const std::string& first_duplicate() const { return first_duplicate_; }

 private:
  struct Frame {
    bool is_object;
    std::string pointer;
    std::set<std::string> keys;
    std::string last_key;
    std::size_t next_index;
  };
  std::string child_pointer() const {
    if (frames_.empty()) return "";
    const Frame& parent = frames_.back();
    return parent.pointer + "/" +
           (parent.is_object ? json_pointer_token(parent.last_key)
                             : std::to_string(parent.next_index));
  }
  void finish_child() {
    if (!frames_.empty() && !frames_.back().is_object) ++frames_.back().next_index;
  }
  std::vector<Frame> frames_;
  std::string first_duplicate_;
};

}  // namespace

std::string json_pointer_token(std::string_view key) {
  std::string token;
  for (char c : key) {
    if (c == '~')
      token += "~0";
    else if (c == '/')
      token += "~1";
    else
      token += c;
  }
  return token;
}

std::string json_value_preview(const Json& value) {
  std::string text = value.dump(-1, ' ', false, Json::error_handler_t::replace);
  constexpr std::size_t kMaxChars = 60;
  if (text.size() > kMaxChars) text = text.substr(0, kMaxChars) + "...";
  return text;
}

namespace {

// "line L, column C" of byte `offset` in text (both from 1).
std::string text_position(const std::string& text, std::size_t offset) {
  std::size_t line = 1, column = 1;
  for (std::size_t i = 0; i < offset && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

// Refuses nesting deeper than kMaxJsonDepth before anything is parsed: the
// parser's work and memory grow with depth (200,000 nested brackets, a
// 400 KB file, once took gigabytes), and no hapticbench file needs more
// than a handful of levels.
void check_json_depth(const std::string& text, const std::string& source) {
  std::size_t depth = 0;
  bool in_string = false, escaped = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (escaped)
        escaped = false;
      else if (c == '\\')
        escaped = true;
      else if (c == '"')
        in_string = false;
      continue;
    }
    if (c == '/' && i + 1 < text.size() && (text[i + 1] == '/' || text[i + 1] == '*')) {
      // A comment (the parser skips them): its brackets and quotes count for nothing.
      const bool line = text[i + 1] == '/';
      const std::size_t end = line ? text.find('\n', i + 2) : text.find("*/", i + 2);
      if (end == std::string::npos) return;  // the parser reports an unclosed comment
      i = line ? end : end + 1;
      continue;
    }
    if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxJsonDepth)
        throw InputError(source, text_position(text, i),
                         "JSON nested deeper than " + std::to_string(kMaxJsonDepth) +
                             " levels (hapticbench files need far fewer)");
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
}

// Where a number that overflows a double is written, from nlohmann's
// message "... number overflow parsing '1e999'".
std::string overflow_position(const std::string& text, const std::string& what) {
  const std::size_t open = what.rfind(" '"), close = what.rfind('\'');
  if (open == std::string::npos || close == std::string::npos || close <= open + 2) return "";
  const std::size_t at = text.find(what.substr(open + 2, close - open - 2));
  return at == std::string::npos ? "" : text_position(text, at);
}

}  // namespace

Json parse_json_document(const std::string& text, const std::string& source) {
  check_json_depth(text, source);
  DuplicateKeyFinder finder;
  Json document;
  try {
    // Comments (// to the end of the line, /* ... */) are allowed: a
    // scenario written by `hapticbench init` explains itself in them.
    document = Json::parse(
        text,
        [&finder](int, nlohmann::json::parse_event_t event, Json& parsed) {
          return finder.on_event(event, parsed);
        },
        /*allow_exceptions=*/true, /*ignore_comments=*/true);
  } catch (const Json::parse_error& error) {
    // nlohmann's text: "[json.exception.parse_error.101] parse error at line 3,
    // column 5: syntax error while parsing ...". Keep the position as the
    // location and the explanation as the message.
    const std::string what = error.what();
    const std::size_t at = what.find("at line ");
    const std::size_t colon = at == std::string::npos ? at : what.find(": ", at);
    if (colon != std::string::npos)
      throw InputError(source, what.substr(at + 3, colon - at - 3),
                       "malformed JSON: " + what.substr(colon + 2));
    throw InputError(source, "byte " + std::to_string(error.byte), "malformed JSON: " + what);
  } catch (const Json::out_of_range& error) {
    throw InputError(source, overflow_position(text, error.what()),
                     "a number too large for a double (largest about 1.8e308)");
  }
  if (!finder.first_duplicate().empty())
    throw InputError(source, finder.first_duplicate(),
                     "key given twice in the same object (each key may appear once)");
  return document;
}

void JsonField::fail(const std::string& expected) const {
  throw InputError(source_, pointer_, expected + ", got " + json_value_preview(*value_));
}

void JsonField::fail_with(const std::string& message) const {
  throw InputError(source_, pointer_, message);
}

void JsonField::require_object(const std::string& expected) const {
  if (!value_->is_object()) fail(expected);
}

void JsonField::reject_unknown_keys(const std::vector<std::string_view>& known,
                                    std::string_view noun) const {
  std::vector<std::string> unknown;
  for (const auto& item : value_->items())
    if (std::find(known.begin(), known.end(), item.key()) == known.end())
      unknown.push_back(item.key());
  if (unknown.empty()) return;

  std::string allowed;
  for (std::string_view key : known) allowed += (allowed.empty() ? "" : ", ") + std::string(key);
  std::string message = "unknown " + std::string(noun) + (unknown.size() == 1 ? "" : "s");
  for (std::size_t i = 0; i < unknown.size(); ++i)
    message += (i == 0 ? " \"" : ", \"") + unknown[i] + "\"";
  if (unknown.size() == 1) {
    // A near miss is most likely a typo of an allowed key (longer names
    // leave room for more slips, e.g. a dropped unit suffix "_us").
    std::string_view closest;
    std::size_t best = unknown[0].size() >= 8 ? 4 : 3;
    for (std::string_view key : known) {
      const std::size_t distance = edit_distance(unknown[0], key);
      if (distance < best) {
        best = distance;
        closest = key;
      }
    }
    if (!closest.empty()) message += " (did you mean \"" + std::string(closest) + "\"?)";
  }
  message += "; allowed here: " + allowed;
  throw InputError(source_, pointer_ + "/" + json_pointer_token(unknown[0]), message);
}

bool JsonField::has(const std::string& key) const {
  return value_->is_object() && value_->contains(key);
}

JsonField JsonField::member(const std::string& key, const std::string& expected) const {
  const std::string pointer = pointer_ + "/" + json_pointer_token(key);
  if (!has(key)) throw InputError(source_, pointer, "missing; expected " + expected);
  return JsonField(value_->at(key), source_, pointer);
}

JsonField JsonField::existing_member(const std::string& key) const {
  return JsonField(value_->at(key), source_, pointer_ + "/" + json_pointer_token(key));
}

std::size_t JsonField::array_size(const std::string& expected) const {
  if (!value_->is_array()) fail(expected);
  return value_->size();
}

JsonField JsonField::element(std::size_t index) const {
  return JsonField(value_->at(index), source_, pointer_ + "/" + std::to_string(index));
}

double JsonField::number(const std::string& expected) const {
  if (!value_->is_number()) fail(expected);
  const double value = value_->get<double>();
  if (!std::isfinite(value)) fail(expected);
  return value;
}

double JsonField::positive_number(const std::string& expected) const {
  const double value = number(expected);
  if (!(value > 0)) fail(expected);
  return value;
}

double JsonField::non_negative_number(const std::string& expected) const {
  const double value = number(expected);
  if (!(value >= 0)) fail(expected);
  return value;
}

int64_t JsonField::integer(int64_t min, int64_t max, const std::string& expected) const {
  if (value_->is_number_unsigned()) {
    const uint64_t value = value_->get<uint64_t>();
    if (value > static_cast<uint64_t>(std::numeric_limits<int64_t>::max()) ||
        static_cast<int64_t>(value) < min || static_cast<int64_t>(value) > max)
      fail(expected);
    return static_cast<int64_t>(value);
  }
  if (value_->is_number_integer()) {
    const int64_t value = value_->get<int64_t>();
    if (value < min || value > max) fail(expected);
    return value;
  }
  // 3.0 is a whole number too; 3.5 and 1e300 are not acceptable.
  const double value = number(expected);
  if (value != std::floor(value) || value < static_cast<double>(min) ||
      value > static_cast<double>(max))
    fail(expected);
  return static_cast<int64_t>(value);
}

std::string JsonField::string(const std::string& expected) const {
  if (!value_->is_string()) fail(expected);
  return value_->get<std::string>();
}

std::string JsonField::file_name_inside(const std::string& expected) const {
  const std::string name = string(expected);
  if (name.empty() || name == "." || name == ".." || name.find('/') != std::string::npos ||
      name.find('\0') != std::string::npos)
    fail(expected + ", a name inside the folder (no '/', not \".\" or \"..\")");
  return name;
}

bool JsonField::boolean(const std::string& expected) const {
  if (!value_->is_boolean()) fail(expected);
  return value_->get<bool>();
}

std::string JsonField::choice(std::initializer_list<std::string_view> allowed) const {
  return choice(std::vector<std::string_view>(allowed));
}

std::string JsonField::choice(const std::vector<std::string_view>& allowed) const {
  std::string expected = "expected one of";
  for (std::size_t i = 0; i < allowed.size(); ++i)
    expected += (i == 0 ? " \"" : ", \"") + std::string(allowed[i]) + "\"";
  const std::string value = string(expected);
  if (std::find(allowed.begin(), allowed.end(), value) == allowed.end()) fail(expected);
  return value;
}

std::vector<double> JsonField::numbers(std::size_t n, const std::string& expected) const {
  if (!value_->is_array() || value_->size() != n) fail(expected);
  std::vector<double> values;
  for (std::size_t i = 0; i < n; ++i) {
    const Json& item = (*value_)[i];
    if (!item.is_number() || !std::isfinite(item.get<double>())) fail(expected);
    values.push_back(item.get<double>());
  }
  return values;
}

Vec3 JsonField::vec3(const std::string& expected) const {
  const std::vector<double> v = numbers(3, expected);
  return Vec3(v[0], v[1], v[2]);
}

}  // namespace hb
