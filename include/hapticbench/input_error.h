// The one error type for bad input: a file, a place in it, and what was
// expected. The command line maps it to exit code 2.
#pragma once

#include <stdexcept>
#include <string>

namespace hb {

/// Bad user input. source: file path (or "" when not from a file);
/// location: where in it, e.g. a JSON path "/algorithms/0/params/k",
/// "line 12", "triangle 37", or a settings field "params.voxel_size".
class InputError : public std::runtime_error {
 public:
  InputError(std::string source, std::string location, const std::string& message)
      : std::runtime_error(format(source, location, message)),
        source_(std::move(source)),
        location_(std::move(location)),
        message_(message) {}

  const std::string& source() const { return source_; }
  const std::string& location() const { return location_; }
  /// What was expected (and found), without source and location.
  const std::string& message() const { return message_; }

 private:
  static std::string format(const std::string& source, const std::string& location,
                            const std::string& message) {
    std::string text;
    if (!source.empty()) text += source + ": ";
    if (!location.empty()) text += location + ": ";
    return text + message;
  }
  std::string source_;
  std::string location_;
  std::string message_;
};

}  // namespace hb
