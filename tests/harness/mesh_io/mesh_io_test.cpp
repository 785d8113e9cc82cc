// Tests for harness/mesh_io/mesh_io.cpp: small files of every format written
// to a temporary folder, read back, and checked against what was written;
// bad files and bad arguments give InputErrors naming the file.
#include "harness/mesh_io/mesh_io.h"

#include <unistd.h>

#include <catch2/catch.hpp>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "hapticbench/input_error.h"
#include "hapticbench/mass_properties.h"
#include "tests/support/scratch_dir.h"

namespace hb {
namespace {

namespace fs = std::filesystem;

// Corner tetrahedron 0, e_x, e_y, e_z (volume 1/6), faces outward.
const char* const kTetrahedronOff =
    "OFF\n4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
    "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";

// Unit cube [0,1]^3 as six quads, counter-clockwise seen from outside.
// Vertex i has coordinates (i & 1, (i >> 1) & 1, (i >> 2) & 1).
const char* const kCubeVertices = "0 0 0\n1 0 0\n0 1 0\n1 1 0\n0 0 1\n1 0 1\n0 1 1\n1 1 1\n";
const int kCubeQuads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                              {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};

std::string cube_faces(const std::string& prefix, int base) {
  std::string text;
  for (const auto& quad : kCubeQuads) {
    text += prefix;
    for (int corner : quad) text.append(" ").append(std::to_string(corner + base));
    text += "\n";
  }
  return text;
}

void check_unit_cube(const TriangleMesh& mesh, double scale = 1.0) {
  CHECK(mesh.vertices.size() == 8);
  CHECK(mesh.triangles.size() == 12);  // each quad split in two
  CHECK_FALSE(find_mesh_defect(mesh));
  CHECK(mass_properties_from_density(mesh, 1.0).volume_m3 == Approx(scale * scale * scale));
  CHECK(mesh.bounds().max().isApprox(Vec3::Constant(scale)));
}

template <typename F>
std::string input_error_text(F&& f) {
  try {
    f();
  } catch (const InputError& error) {
    return error.what();
  }
  FAIL("expected InputError");
  return "";
}

}  // namespace

TEST_CASE("OFF tetrahedron", "[mesh_io]") {
  const test::ScratchDir folder("mesh_io");
  const TriangleMesh mesh = read_mesh_file(folder.write("tetra.off", kTetrahedronOff));
  CHECK(mesh.vertices.size() == 4);
  CHECK(mesh.triangles.size() == 4);
  CHECK_FALSE(find_mesh_defect(mesh));
  CHECK(mass_properties_from_density(mesh, 1.0).volume_m3 == Approx(1.0 / 6.0));
}

TEST_CASE("OFF cube of quads is split into outward triangles", "[mesh_io]") {
  const test::ScratchDir folder("mesh_io");
  const std::string text = std::string("OFF\n8 6 12\n") + kCubeVertices + cube_faces("4", 0);
  check_unit_cube(read_mesh_file(folder.write("cube.off", text)));
  // Upper-case extensions are the same format.
  check_unit_cube(read_mesh_file(folder.write("CUBE.OFF", text)));
}

TEST_CASE("OBJ cube (1-based indices)", "[mesh_io]") {
  const test::ScratchDir folder("mesh_io");
  std::string text = "# unit cube\no cube\n";
  for (int i = 0; i < 8; ++i)
    text += "v " + std::to_string(i & 1) + " " + std::to_string((i >> 1) & 1) + " " +
            std::to_string((i >> 2) & 1) + "\n";
  text += cube_faces("f", 1);
  check_unit_cube(read_mesh_file(folder.write("cube.obj", text)));
}

TEST_CASE("ASCII STL: unconnected triangles are merged at shared corners", "[mesh_io]") {
  const test::ScratchDir folder("mesh_io");
  const double corner[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const int faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  std::string text = "solid tetra\n";
  for (const auto& face : faces) {
    text += " facet normal 0 0 0\n  outer loop\n";
    for (int c : face)
      text += "   vertex " + std::to_string(corner[c][0]) + " " + std::to_string(corner[c][1]) +
              " " + std::to_string(corner[c][2]) + "\n";
    text += "  endloop\n endfacet\n";
  }
  text += "endsolid tetra\n";
  const TriangleMesh mesh = read_mesh_file(folder.write("tetra.stl", text), 0.001);
  CHECK(mesh.vertices.size() == 4);
  CHECK(mesh.triangles.size() == 4);
  CHECK_FALSE(find_mesh_defect(mesh));
  CHECK(mass_properties_from_density(mesh, 1.0).volume_m3 == Approx(1e-9 / 6.0));
}

TEST_CASE("ASCII PLY cube of quads", "[mesh_io]") {
  const test::ScratchDir folder("mesh_io");
  const std::string text =
      std::string(
          "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\n"
          "property float z\nelement face 6\nproperty list uchar int vertex_indices\n"
          "end_header\n") +
      kCubeVertices + cube_faces("4", 0);
  check_unit_cube(read_mesh_file(folder.write("cube.ply", text), 2.5), 2.5);
}

TEST_CASE("coincident vertices in any format are merged", "[mesh_io]") {
  const test::ScratchDir folder("mesh_io");
  // The tetrahedron with every face given its own three vertices; -0 and 0
  // are the same coordinate.
  const std::string text =
      "OFF\n12 4 0\n"
      "0 0 0\n0 1 0\n1 0 0\n"
      "-0 0 0\n1 0 0\n0 0 1\n"
      "0 -0 0\n0 0 1\n0 1 0\n"
      "1 0 0\n0 1 0\n0 0 1\n"
      "3 0 1 2\n3 3 4 5\n3 6 7 8\n3 9 10 11\n";
  const TriangleMesh mesh = read_mesh_file(folder.write("soup.off", text));
  CHECK(mesh.vertices.size() == 4);
  CHECK_FALSE(find_mesh_defect(mesh));
}

TEST_CASE("scale multiplies every coordinate and must be positive", "[mesh_io]") {
  const test::ScratchDir folder("mesh_io");
  const std::string path = folder.write("tetra.off", kTetrahedronOff);
  const TriangleMesh mesh = read_mesh_file(path, 0.02);
  CHECK(mesh.bounds().max().isApprox(Vec3(0.02, 0.02, 0.02)));
  for (double bad : {0.0, -1.0, double(NAN), double(INFINITY)}) {
    INFO("scale " << bad);
    CHECK_THAT(input_error_text([&] { read_mesh_file(path, bad); }),
               Catch::Contains(path) && Catch::Contains("scale"));
  }
}

TEST_CASE("missing file, unknown extension and garbage name the file", "[mesh_io]") {
  const test::ScratchDir folder("mesh_io");
  const std::string missing = (folder.path() / "nowhere.off").string();
  CHECK_THAT(input_error_text([&] { read_mesh_file(missing); }),
             Catch::Contains(missing) && Catch::Contains("file not found"));

  const std::string xyz = folder.write("points.xyz", "0 0 0\n");
  CHECK_THAT(input_error_text([&] { read_mesh_file(xyz); }),
             Catch::Contains(xyz) && Catch::Contains("\".xyz\"") &&
                 Catch::Contains(".off, .obj, .stl, .ply"));

  const std::string none = folder.write("mesh", kTetrahedronOff);
  CHECK_THAT(input_error_text([&] { read_mesh_file(none); }), Catch::Contains(none));

  const std::string garbage = "this is not a mesh\n\x01\x02 3 4 5\n";
  CHECK_THAT(input_error_text([&] { read_mesh_file(folder.write("bad.off", garbage)); }),
             Catch::Contains("bad.off") && Catch::Contains("expected the keyword OFF"));
  CHECK_THAT(input_error_text([&] { read_mesh_file(folder.write("bad.obj", garbage)); }),
             Catch::Contains("bad.obj") && Catch::Contains("could not parse as OBJ"));
  // PLY headers are checked line by line before the reader sees them.
  CHECK_THAT(input_error_text([&] { read_mesh_file(folder.write("bad.ply", garbage)); }),
             Catch::Contains("bad.ply") && Catch::Contains("line 1") &&
                 Catch::Contains("expected \"ply\" on the first line"));
  // Binary STL (not starting with "solid"): header and count are checked first.
  CHECK_THAT(input_error_text([&] { read_mesh_file(folder.write("bad.stl", garbage)); }),
             Catch::Contains("bad.stl") && Catch::Contains("at least 84 bytes"));
  CHECK_THAT(input_error_text([&] { read_mesh_file(folder.write("empty.off", "")); }),
             Catch::Contains("empty.off"));
}

TEST_CASE("a face's corner count is read as the reader reads it", "[mesh_io]") {
  // The readers take the digits a word starts with ("2000000000" from
  // "2000000000\x1f...") and a leading '+': the check must too (found by
  // fuzzing: each made the reader allocate 16 GB).
  const test::ScratchDir folder("mesh_io");
  const std::string head = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n";
  for (const std::string& face :
       {std::string("2000000000\x1f\x15 0 1 2\n"), std::string("+2000000000 0 1 2\n")}) {
    CHECK_THAT(input_error_text([&] { read_mesh_file(folder.write("count.off", head + face)); }),
               Catch::Contains("count.off: line 6") &&
                   Catch::Contains("declares 2000000000 corners but the line lists 3"));
  }
  // The keyword ends at its first character that is not a letter or digit,
  // which the reader consumes: "OFF>3 1 0" declares 3 vertices and 1 face.
  CHECK_THAT(
      input_error_text([&] {
        read_mesh_file(
            folder.write("glued.off", "OFF>3 1 0\n0 1 0\n1 0 0\n0 1 0\n20000000000 4 1 2\n"));
      }),
      Catch::Contains("glued.off: line 5") && Catch::Contains("declares 20000000000 corners"));
  // PLY vertex coordinates must be float or double: an int16 "z" crashed
  // the reader (found by fuzzing).
  CHECK_THAT(input_error_text([&] {
               read_mesh_file(folder.write(
                   "short.ply",
                   "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                   "property int16 z\nelement face 1\nproperty list uchar int vertex_indices\n"
                   "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"));
             }),
             Catch::Contains("short.ply: line 6") &&
                 Catch::Contains("vertex coordinate \"z\" has type \"int16\""));
  // Binary OFF is refused: its raw counts were trusted (4 GB from 200 bytes).
  CHECK_THAT(input_error_text([&] {
               read_mesh_file(folder.write("binary.off", "OFF\n\nBINARY]\n\n\n\n\x9e\n"));
             }),
             Catch::Contains("binary.off: line 1") && Catch::Contains("binary OFF is not read"));
}

TEST_CASE("a binary STL's triangle count must fit the file", "[mesh_io]") {
  const test::ScratchDir folder("mesh_io");
  // One triangle: 80-byte header, count 1, normal, three corners, attribute.
  std::string one(84 + 50, '\0');
  one[80] = 1;
  const float corners[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  std::memcpy(one.data() + 84 + 12, corners, sizeof corners);
  CHECK(read_mesh_file(folder.write("one.stl", one)).triangles.size() == 1);
  std::string lying = one;
  lying[83] = 0x30;  // 805,306,369 triangles in 134 bytes
  CHECK_THAT(input_error_text([&] { read_mesh_file(folder.write("lying.stl", lying)); }),
             Catch::Contains("lying.stl: triangle count") &&
                 Catch::Contains("declares 805306369 triangles"));
}

TEST_CASE("no reader allocates for a count its bytes cannot hold", "[mesh_io]") {
  const test::ScratchDir folder("mesh_io");
  const std::string ply_head = "ply\nformat ascii 1.0\n";
  const std::string xyz = "property float x\nproperty float y\nproperty float z\n";
  const std::string face_list = "property list uchar int vertex_indices\n";
  // A header count above what the file's bytes can hold.
  CHECK_THAT(input_error_text([&] {
               read_mesh_file(folder.write("count.ply", ply_head + "element vertex 1000000000\n" +
                                                            xyz + "element face 1\n" + face_list +
                                                            "end_header\n0 0 0\n"));
             }),
             Catch::Contains("count.ply: header") &&
                 Catch::Contains("declares 1000000000 elements of \"vertex\""));
  // An ASCII list longer than its line.
  CHECK_THAT(input_error_text([&] {
               read_mesh_file(folder.write("list.ply", ply_head + "element vertex 3\n" + xyz +
                                                           "element face 1\n" + face_list +
                                                           "end_header\n0 0 0\n1 0 0\n0 1 0\n"
                                                           "2000000000 0 1 2\n"));
             }),
             Catch::Contains("list.ply: line 13") &&
                 Catch::Contains("a list declares 2000000000 entries but the line has 3"));
  // Binary PLY: elements that need more bytes than are left, and a list
  // count of 2^32 - 1 with a few bytes behind it.
  const std::string binary_head =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\n" + xyz + "element face 1\n";
  std::string corners(36, '\0');
  const float one = 1.0f;
  std::memcpy(corners.data() + 12, &one, 4);
  std::memcpy(corners.data() + 28, &one, 4);
  const std::string triangle_ply =
      binary_head + face_list + "end_header\n" + corners +
      std::string("\x03\x00\x00\x00\x00\x01\x00\x00\x00\x02\x00\x00\x00", 13);
  const TriangleMesh one_triangle = read_mesh_file(folder.write("triangle.ply", triangle_ply));
  CHECK(one_triangle.triangles.size() == 1);
  CHECK(one_triangle.vertices.size() == 3);
  CHECK_THAT(input_error_text([&] {
               read_mesh_file(folder.write(
                   "short.ply", binary_head + face_list + "end_header\n" + corners.substr(0, 20)));
             }),
             Catch::Contains("short.ply: element vertex") && Catch::Contains("need at least 36"));
  const std::string long_list = binary_head + "property list uint int vertex_indices\n" +
                                "end_header\n" + corners + std::string("\xff\xff\xff\xff", 4) +
                                std::string(12, '\0');
  CHECK_THAT(input_error_text([&] { read_mesh_file(folder.write("long.ply", long_list)); }),
             Catch::Contains("long.ply: element face 0") &&
                 Catch::Contains("a list declares 4294967295 entries; 12 bytes are left"));
  // OBJ declares no counts: a face lists what its line holds, and corners
  // counting back past the first vertex are refused.
  CHECK_THAT(input_error_text([&] {
               read_mesh_file(folder.write("back.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n"));
             }),
             Catch::Contains("back.obj: line 4") && Catch::Contains("counts back past the first"));
  // ASCII STL: a facet's loop holds three vertices.
  CHECK_THAT(
      input_error_text([&] {
        read_mesh_file(folder.write("four.stl",
                                    "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                                    "vertex 1 0 0\nvertex 0 1 0\nvertex 1 1 0\nendloop\nendfacet\n"
                                    "endsolid s\n"));
      }),
      Catch::Contains("four.stl: line 7") && Catch::Contains("more than three vertices"));
}

TEST_CASE("face with an out-of-range vertex index", "[mesh_io]") {
  const test::ScratchDir folder("mesh_io");
  const std::string path =
      folder.write("broken.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 9\n");
  CHECK_THAT(input_error_text([&] { read_mesh_file(path); }), Catch::Contains("broken.off"));
}

TEST_CASE("Stanford bunny from CGAL's data, if installed", "[mesh_io]") {
  const fs::path archive = "/usr/share/doc/libcgal-dev/data.tar.gz";
  if (!fs::exists(archive)) {
    WARN("skipped: " << archive << " is not installed");
    return;
  }
  const test::ScratchDir folder("mesh_io");
  const std::string command =
      "tar -xzf " + archive.string() + " -C " + folder.path().string() + " data/meshes/bunny00.off";
  if (std::system(command.c_str()) != 0) {
    WARN("skipped: could not extract bunny00.off from " << archive);
    return;
  }
  const std::string path = (folder.path() / "data/meshes/bunny00.off").string();
  // The OFF header states the counts; every face is a triangle.
  std::ifstream header(path);
  std::string magic;
  std::size_t vertex_count = 0, face_count = 0;
  header >> magic >> vertex_count >> face_count;
  REQUIRE(magic == "OFF");

  const TriangleMesh mesh = read_mesh_file(path, 0.1);
  CHECK(mesh.vertices.size() == vertex_count);
  CHECK(mesh.triangles.size() == face_count);
  CHECK_FALSE(find_mesh_defect(mesh));
  CHECK(mass_properties_from_density(mesh, 1000.0).mass_kg > 0.0);
}

TEST_CASE("CGAL's PLY and STL files read as the closed meshes they are, if installed",
          "[mesh_io]") {
  const fs::path archive = "/usr/share/doc/libcgal-dev/data.tar.gz";
  if (!fs::exists(archive)) {
    WARN("skipped: " << archive << " is not installed");
    return;
  }
  const test::ScratchDir folder("mesh_io");
  const std::string command = "tar -xzf " + archive.string() + " -C " + folder.path().string() +
                              " data/meshes/sphere.ply data/meshes/sphere.stl"
                              " data/meshes/colored_tetra.ply data/meshes/pig.stl";
  REQUIRE(std::system(command.c_str()) == 0);
  const fs::path meshes = folder.path() / "data/meshes";
  // ASCII PLY of an icosphere: 162 vertices, 320 triangles, as its header says.
  const TriangleMesh sphere_ply = read_mesh_file((meshes / "sphere.ply").string());
  CHECK(sphere_ply.vertices.size() == 162);
  CHECK(sphere_ply.triangles.size() == 320);
  CHECK_FALSE(find_mesh_defect(sphere_ply));
  // Binary STL (its header starts with neither "solid" nor a count that
  // lies): every triangle's own corners merge into a closed surface.
  const TriangleMesh sphere_stl = read_mesh_file((meshes / "sphere.stl").string());
  CHECK(sphere_stl.triangles.size() == (fs::file_size(meshes / "sphere.stl") - 84) / 50);
  CHECK_FALSE(find_mesh_defect(sphere_stl));
  const TriangleMesh pig = read_mesh_file((meshes / "pig.stl").string());
  CHECK(pig.triangles.size() == (fs::file_size(meshes / "pig.stl") - 84) / 50);
  CHECK(pig.vertices.size() < pig.triangles.size());
  // Doubles with normals, colours and an id beside them; a list per face.
  const TriangleMesh tetra = read_mesh_file((meshes / "colored_tetra.ply").string());
  CHECK(tetra.vertices.size() == 4);
  CHECK(tetra.triangles.size() == 4);
  CHECK_FALSE(find_mesh_defect(tetra));
}

}  // namespace hb
