// Mesh files: OBJ and STL (ASCII, binary) of one mesh load to the same indexed mesh, in either
// unit; broken files give errors that say where and what.
#include "engine/geometry/mesh_io.hpp"

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "engine/core/input_file.hpp"
#include "engine/geometry/mesh_shapes.hpp"

namespace acdr {
namespace {

TriangleMesh test_sphere() { return make_sphere_mesh(Vec3(1.5e-3, -2e-3, 3.25e-3), 4e-3, 2); }

TEST(MeshIo, ObjAndStlOfTheSameMeshLoadIdentically) {
  const TriangleMesh m = test_sphere();
  std::string e1, e2, e3;
  const auto obj = read_obj(mesh_file_bytes(m, MeshFormat::kObj, LengthUnit::kMillimetre), "s.obj",
                            LengthUnit::kMillimetre, &e1);
  const auto bin = read_stl(mesh_file_bytes(m, MeshFormat::kStlBinary, LengthUnit::kMillimetre),
                            "s.stl", LengthUnit::kMillimetre, &e2);
  const auto asc = read_stl(mesh_file_bytes(m, MeshFormat::kStlAscii, LengthUnit::kMillimetre),
                            "s.stl", LengthUnit::kMillimetre, &e3);
  ASSERT_TRUE(obj) << e1;
  ASSERT_TRUE(bin) << e2;
  ASSERT_TRUE(asc) << e3;
  EXPECT_EQ(obj->vertex_count(), m.vertex_count());
  EXPECT_EQ(bin->vertex_count(), m.vertex_count());  // STL's 3 copies per triangle welded
  EXPECT_EQ(obj->triangles, bin->triangles);
  EXPECT_EQ(obj->content_hash(), bin->content_hash());
  EXPECT_EQ(obj->content_hash(), asc->content_hash());
  EXPECT_TRUE(check_closed_mesh(*bin).ok);
  // Single precision on file: within a few nanometres of the original (renumbered by first
  // use, as welding does).
  TriangleMesh renumbered = m;
  renumbered.weld_exact();
  for (std::size_t i = 0; i < m.vertex_count(); ++i) {
    EXPECT_NEAR((obj->vertices[i] - renumbered.vertices[i]).norm(), 0.0, 5e-9);
  }
}

TEST(MeshIo, UnitsAreTheCallersDeclaration) {
  const TriangleMesh m = make_box_mesh(Vec3(0, 0, 0), Vec3(0.01, 0.02, 0.03));
  const std::string in_m = mesh_file_bytes(m, MeshFormat::kStlBinary, LengthUnit::kMetre);
  std::string error;
  const auto as_mm = read_stl(in_m, "box.stl", LengthUnit::kMillimetre, &error);
  ASSERT_TRUE(as_mm) << error;
  Vec3 lo, hi;
  as_mm->bounds(&lo, &hi);
  EXPECT_NEAR(hi.z(), 0.03e-3, 1e-12);  // 0.03 read as millimetres
  const auto as_m = read_stl(in_m, "box.stl", LengthUnit::kMetre, &error);
  as_m->bounds(&lo, &hi);
  EXPECT_NEAR(hi.z(), 0.03, 1e-8);
}

TEST(MeshIo, ObjPolygonsAndNegativeIndicesAreAccepted) {
  const std::string text =
      "# a unit cube written with quads\n"
      "o cube\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
      "vn 0 0 1\n"
      "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\n"
      "f -8//1 -4//1 -1//1 -5//1\n";
  std::string error;
  const auto m = read_obj(text, "cube.obj", LengthUnit::kMillimetre, &error);
  ASSERT_TRUE(m) << error;
  EXPECT_EQ(m->triangle_count(), 12u);
  const MeshCheck c = check_closed_mesh(*m);
  EXPECT_TRUE(c.ok) << c.error;
  EXPECT_NEAR(c.volume_m3, 1e-9, 1e-20);
}

struct BrokenObj {
  const char* text;
  const char* expected;
};

TEST(MeshIo, BrokenObjNamesTheLine) {
  const BrokenObj cases[] = {
      {"v 0 0 0\nv 1 0 0\nv 0 1\nf 1 2 3\n", "t.obj:3: vertex has 2 coordinates"},
      {"v 0 0 0\nv 1 x 0\nv 0 1 0\nf 1 2 3\n", "t.obj:2: vertex coordinate 2 is not a finite number (got 'x')"},
      {"v 0 0 0\nv 1 1e39 0\nv 0 1 0\nf 1 2 3\n",
       "t.obj:2: vertex coordinate 2 is outside the range of a 32-bit float (got '1e39'"},
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "t.obj:4: face refers to vertex 4, but the file has 3 vertices"},
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", "t.obj:4: face has 2 vertices"},
      // A form feed before "v" makes the line no vertex for the OBJ reader, so not for the
      // check either (found by the fuzzer: the two disagreed and a face index ran past the end).
      {"v 0 0 0\nv 1 0 0\n\fv 0 1 0\nf 1 2 3\n",
       "t.obj:4: face refers to vertex 3, but the file has 2 vertices"},
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 a\n", "t.obj:4: face vertex 'a' is not an index"},
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\n", "no faces"},
      {"# nothing\n", "no vertices"},
  };
  for (const BrokenObj& c : cases) {
    std::string error;
    EXPECT_FALSE(read_obj(c.text, "t.obj", LengthUnit::kMillimetre, &error)) << c.text;
    EXPECT_NE(error.find(c.expected), std::string::npos) << "got: " << error;
  }
}

TEST(MeshIo, BrokenStlNamesTheLineOrByte) {
  const TriangleMesh m = make_box_mesh(Vec3(0, 0, 0), Vec3(1e-3, 1e-3, 1e-3));
  std::string error;

  std::string truncated = mesh_file_bytes(m, MeshFormat::kStlBinary, LengthUnit::kMillimetre);
  truncated.resize(truncated.size() - 10);
  EXPECT_FALSE(read_stl(truncated, "b.stl", LengthUnit::kMillimetre, &error));
  EXPECT_NE(error.find("declares 12 triangles (684 bytes) but the file has 674 bytes"),
            std::string::npos) << error;

  std::string nan_file = mesh_file_bytes(m, MeshFormat::kStlBinary, LengthUnit::kMillimetre);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(nan_file.data() + 84 + 50 * 2 + 12 + 12 + 4, &nan, 4);  // triangle 2, vertex 2, y
  EXPECT_FALSE(read_stl(nan_file, "b.stl", LengthUnit::kMillimetre, &error));
  EXPECT_NE(error.find("b.stl: byte 208: triangle 2 vertex 2 is not a finite number"),
            std::string::npos) << error;

  const std::string ascii = mesh_file_bytes(m, MeshFormat::kStlAscii, LengthUnit::kMillimetre);
  std::string bad_number = ascii;
  bad_number[bad_number.find("vertex ") + 7] = 'q';
  EXPECT_FALSE(read_stl(bad_number, "a.stl", LengthUnit::kMillimetre, &error));
  EXPECT_NE(error.find("a.stl:4: vertex coordinate 1 is not a finite number"), std::string::npos)
      << error;

  // A finite double beyond a float's range would be an infinite vertex (a fuzzing finding).
  std::string huge = "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1e39 0 0\n"
                     "vertex 1 1 0\nendloop\nendfacet\nendsolid\n";
  EXPECT_FALSE(read_stl(huge, "a.stl", LengthUnit::kMillimetre, &error));
  EXPECT_NE(error.find("a.stl:5: vertex coordinate 1 is outside the range of a 32-bit float"),
            std::string::npos) << error;

  const std::string cut = ascii.substr(0, ascii.size() / 2);
  EXPECT_FALSE(read_stl(cut, "a.stl", LengthUnit::kMillimetre, &error));
  EXPECT_NE(error.find("truncated"), std::string::npos) << error;

  std::string four = "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
                     "vertex 1 1 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid\n";
  EXPECT_FALSE(read_stl(four, "a.stl", LengthUnit::kMillimetre, &error));
  EXPECT_NE(error.find("a.stl:7: facet has more than 3 vertices"), std::string::npos) << error;

  EXPECT_FALSE(read_stl("hello", "x.stl", LengthUnit::kMillimetre, &error));
  EXPECT_NE(error.find("not an STL file"), std::string::npos) << error;
}

TEST(MeshIo, FilesRoundTripAndOpenMeshesAreRefused) {
  const auto dir = std::filesystem::temp_directory_path() / "acdr_mesh_io_test";
  std::filesystem::create_directories(dir);
  const TriangleMesh m = test_sphere();
  std::string error;
  const std::string obj = (dir / "s.OBJ").string(), stl = (dir / "s.stl").string();
  ASSERT_TRUE(save_mesh_file(m, obj, MeshFormat::kObj, LengthUnit::kMetre, &error)) << error;
  ASSERT_TRUE(save_mesh_file(m, stl, MeshFormat::kStlBinary, LengthUnit::kMetre, &error)) << error;
  const auto a = load_closed_mesh_file(obj, LengthUnit::kMetre, &error);
  const auto b = load_closed_mesh_file(stl, LengthUnit::kMetre, &error);
  ASSERT_TRUE(a && b) << error;
  EXPECT_EQ(a->content_hash(), b->content_hash());

  TriangleMesh open = m;
  open.triangles.resize(open.triangles.size() - 5);
  const std::string hole = (dir / "hole.stl").string();
  ASSERT_TRUE(save_mesh_file(open, hole, MeshFormat::kStlBinary, LengthUnit::kMillimetre, &error));
  EXPECT_FALSE(load_closed_mesh_file(hole, LengthUnit::kMillimetre, &error));
  EXPECT_NE(error.find(hole + ": not a closed surface:"), std::string::npos) << error;
  EXPECT_NE(error.find("open edges"), std::string::npos) << error;

  EXPECT_FALSE(load_mesh_file((dir / "missing.stl").string(), LengthUnit::kMetre, &error));
  EXPECT_NE(error.find("cannot open"), std::string::npos) << error;
  EXPECT_FALSE(load_mesh_file((dir / "mesh.ply").string(), LengthUnit::kMetre, &error));
  EXPECT_NE(error.find("expected .obj or .stl"), std::string::npos) << error;
  std::filesystem::remove_all(dir);
}

// A mesh path that leads to a device or a FIFO is refused at once (never read until memory runs
// out, never waited on), and a file over the cap is refused from its size.
TEST(MeshIo, RefusesDevicesFifosAndOversizedFiles) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "acdr_mesh_io_special";
  fs::remove_all(dir);
  fs::create_directories(dir);
  fs::create_symlink("/dev/zero", dir / "zero.stl");
  fs::create_symlink("/dev/urandom", dir / "random.obj");
  ASSERT_EQ(::mkfifo((dir / "pipe.stl").c_str(), 0600), 0);
  for (const char* name : {"zero.stl", "random.obj", "pipe.stl"}) {
    const std::string path = (dir / name).string();
    std::string error;
    const auto t0 = std::chrono::steady_clock::now();
    EXPECT_FALSE(load_mesh_file(path, LengthUnit::kMillimetre, &error));
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 1.0);
    EXPECT_EQ(error.rfind(path + ": not a regular file (got a ", 0), 0u) << error;
  }
  const fs::path big = dir / "big.stl";
  { std::ofstream touch(big); }
  fs::resize_file(big, kMaxMeshFileBytes + 1);
  std::string error;
  EXPECT_FALSE(load_mesh_file(big.string(), LengthUnit::kMillimetre, &error));
  EXPECT_NE(error.find("file too large (got 67108865 bytes, expected at most 67108864"), std::string::npos)
      << error;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace acdr
