#include "algorithms/core/content_hash.h"

#include <cstdio>
#include <fstream>
#include <iterator>

#include "algorithms/core/input_error.h"

namespace hb {

std::string ContentHash::hex() const {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(state_));
  return text;
}

std::string file_content_hash(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "", "cannot open file");
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return ContentHash().add(bytes).hex();
}

}  // namespace hb
