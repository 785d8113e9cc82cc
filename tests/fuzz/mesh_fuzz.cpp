// Fuzz target: mesh files (OFF, OBJ, STL, PLY) through read_mesh_file and
// the mesh checks a scenario applies.
#include "hapticbench/triangle_mesh.h"
#include "harness/mesh_io/mesh_io.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  // The first byte picks the format; the rest is the file.
  static const char* const kNames[] = {"mesh.off", "mesh.obj", "mesh.stl", "mesh.ply"};
  const auto path = hb::fuzz::file_of(data + 1, size - 1, kNames[data[0] % 4]);
  return hb::fuzz::expect_input_errors_only([&] {
    const hb::TriangleMesh mesh = hb::read_mesh_file(path.string(), 1.0);
    (void)hb::find_mesh_defect(mesh);
  });
}
