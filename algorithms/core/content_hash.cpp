#include "hapticbench/content_hash.h"

#include <cstdio>
#include <fstream>
#include <iterator>

#include "hapticbench/input_error.h"

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

std::string exact_key_text(double value) {
  char text[64];
  std::snprintf(text, sizeof text, "%a", value);
  return text;
}

std::string mesh_geometry_hash(const TriangleMesh& mesh) {
  ContentHash hash;
  hash.add(std::string_view(reinterpret_cast<const char*>(mesh.vertices.data()),
                            mesh.vertices.size() * sizeof(Vec3)));
  hash.add(std::string_view(reinterpret_cast<const char*>(mesh.triangles.data()),
                            mesh.triangles.size() * sizeof(mesh.triangles[0])));
  return hash.hex();
}

}  // namespace hb
