// printf-style text of one number, for messages, tables and verdicts.
#pragma once

#include <cstdio>
#include <string>

namespace hb {

/// `format` holds exactly one double conversion, e.g. "%.3g" or "x%.2f".
inline std::string formatted(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

}  // namespace hb
