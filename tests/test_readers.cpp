// The mesh readers: the strict OFF / OBJ / PLY reader against assimp (an independent reader) on
// the same mesh in every encoding, and each kind of malformed file against its message.
#include <gtest/gtest.h>

#include <assimp/Importer.hpp>
#include <assimp/scene.h>

#include <algorithm>
#include <cstdio>
#include <random>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

#include "checks.hpp"
#include <minksum/io.hpp>
#include "support/mesh_io.hpp"

namespace minksum {
namespace {

using Eigen::Vector3d;
namespace fs = std::filesystem;
using Corners = std::vector<std::array<Vector3d, 3>>;

std::string scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("minksum_readers_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return (dir / name).string();
}

Corners corners(const std::vector<Vector3d>& v, const std::vector<std::array<int, 3>>& t) {
  Corners c;
  for (const auto& f : t) c.push_back({v[f[0]], v[f[1]], v[f[2]]});
  return c;
}

// The triangles' corners as assimp reads the file (no post-processing, like the STL path).
Corners assimp_corners(const std::string& path) {
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(path, 0);
  Corners c;
  if (!scene) {
    ADD_FAILURE() << path << ": assimp: " << importer.GetErrorString();
    return c;
  }
  for (unsigned m = 0; m < scene->mNumMeshes; ++m)
    for (unsigned f = 0; f < scene->mMeshes[m]->mNumFaces; ++f) {
      const aiMesh* mesh = scene->mMeshes[m];
      const aiFace& face = mesh->mFaces[f];
      const auto at = [&](unsigned k) {
        const aiVector3D& p = mesh->mVertices[face.mIndices[k]];
        return Vector3d(p.x, p.y, p.z);
      };
      for (unsigned k = 1; k + 1 < face.mNumIndices; ++k) c.push_back({at(0), at(k), at(k + 1)});
    }
  return c;
}

// The same corners: exactly, or within `tol` (assimp's own decimal parser is not correctly
// rounded: 1.26785e-18 in a text file came out one float ulp off).
void expect_same(const Corners& got, const Corners& want, const std::string& what, double tol = 0) {
  ASSERT_EQ(got.size(), want.size()) << what;
  for (size_t f = 0; f < got.size(); ++f)
    for (int k = 0; k < 3; ++k)
      ASSERT_LE((got[f][k] - want[f][k]).cwiseAbs().maxCoeff(), tol)
          << what << ": triangle " << f << " corner " << k << ": " << got[f][k].transpose() << " vs "
          << want[f][k].transpose();
}

// A mesh of quads (fanned into two triangles each by every reader) with float coordinates, so
// that every encoding holds them exactly.
struct QuadMesh {
  std::vector<Vector3d> v;
  std::vector<std::array<int, 4>> quads;
};

QuadMesh quad_mesh() {
  const tools::Mesh m = test::test_mesh("bun_zipper_res4.ply", 12);  // only its vertices are used
  QuadMesh q;
  // Rounded through float component by component (Eigen's cast<float>().cast<double>() was
  // compiled to nothing at -O3 here).
  for (const auto& p : m.vertices) q.v.emplace_back(double(float(p.x())), double(float(p.y())), double(float(p.z())));
  for (int i = 0; i + 3 < int(q.v.size()); i += 3) q.quads.push_back({i, i + 1, i + 2, i + 3});
  return q;
}

template <typename T>
void put(std::ostream& out, T value, bool big_endian) {
  char b[sizeof(T)];
  std::memcpy(b, &value, sizeof(T));
  if (big_endian) std::reverse(b, b + sizeof(T));
  out.write(b, sizeof(T));
}

std::string write_ply(const QuadMesh& q, const std::string& format, const std::string& name) {
  std::ofstream out(scratch(name), std::ios::binary);
  out.precision(9);  // a float round-trips through 9 significant digits
  // An extra property on each element and an element after the faces, which must be skipped.
  out << "ply\nformat " << format << " 1.0\ncomment test\nelement vertex " << q.v.size()
      << "\nproperty float x\nproperty uchar flag\nproperty float y\nproperty float z\nelement face " << q.quads.size()
      << "\nproperty list uchar int vertex_indices\nproperty short tag\n"
      << "element note 1\nproperty list ushort double values\nend_header\n";
  const bool big = format == "binary_big_endian";
  for (const auto& p : q.v)
    if (format == "ascii")
      out << float(p.x()) << " 7 " << float(p.y()) << ' ' << float(p.z()) << '\n';
    else
      put(out, float(p.x()), big), put(out, uint8_t(7), big), put(out, float(p.y()), big), put(out, float(p.z()), big);
  for (const auto& f : q.quads)
    if (format == "ascii")
      out << "4 " << f[0] << ' ' << f[1] << ' ' << f[2] << ' ' << f[3] << " -3\n";
    else
      put(out, uint8_t(4), big), put(out, f[0], big), put(out, f[1], big), put(out, f[2], big), put(out, f[3], big),
          put(out, int16_t(-3), big);
  if (format == "ascii")
    out << "2 0.5 -1e300\n";
  else
    put(out, uint16_t(2), big), put(out, 0.5, big), put(out, -1e300, big);
  return scratch(name);
}

std::string write_text(const std::string& name, const std::string& text) {
  std::ofstream(scratch(name), std::ios::binary) << text;
  return scratch(name);
}

TEST(Readers, EveryEncodingReadsAsAssimpReadsIt) {
  const QuadMesh q = quad_mesh();
  ASSERT_GT(q.quads.size(), 10u);
  double size = 0;
  for (const auto& p : q.v) size = std::max(size, p.cwiseAbs().maxCoeff());
  std::ostringstream off, obj;
  off.precision(17), obj.precision(17);
  off << "OFF\n# a comment\n" << q.v.size() << ' ' << q.quads.size() << " 0\n";
  for (const auto& p : q.v)
    off << p.x() << ' ' << p.y() << ' ' << p.z() << '\n', obj << "v " << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  obj << "vt 0 0\nvn 0 0 1\n";
  for (const auto& f : q.quads) {
    off << "4 " << f[0] << ' ' << f[1] << ' ' << f[2] << ' ' << f[3] << '\n';
    // Absolute, with texture and normal references, and relative (negative) indices.
    obj << "f " << f[0] + 1 << "/1/1 " << f[1] + 1 << "//1 " << f[2] - long(q.v.size()) << ' ' << f[3] + 1 << '\n';
  }
  const std::vector<std::string> files = {
      write_text("m.off", off.str()), write_text("m.obj", obj.str()), write_ply(q, "ascii", "a.ply"),
      write_ply(q, "binary_little_endian", "le.ply"), write_ply(q, "binary_big_endian", "be.ply")};
  Corners want;
  for (const auto& f : q.quads) {
    want.push_back({q.v[f[0]], q.v[f[1]], q.v[f[2]]});
    want.push_back({q.v[f[0]], q.v[f[2]], q.v[f[3]]});
  }
  for (const std::string& file : files) {
    tools::Mesh m;
    std::string error;
    ASSERT_TRUE(tools::read_mesh(file, m, error)) << error;
    EXPECT_EQ(m.vertices.size(), q.v.size()) << file;
    expect_same(corners(m.vertices, m.triangles), want, file);
    expect_same(assimp_corners(file), want, file + " (assimp)", 1e-7 * size);
  }
}

TEST(Readers, BunnyAsAssimpReadsIt) {
  const fs::path path = test::data_path("bun_zipper_res3.ply");
  if (!fs::exists(path)) GTEST_SKIP() << path << " is not there";
  tools::Mesh m;
  std::string error;
  ASSERT_TRUE(tools::read_mesh(path.string(), m, error)) << error;
  EXPECT_EQ(m.vertices.size(), 1889u);  // the header's counts
  EXPECT_EQ(m.triangles.size(), 3851u);
  Corners want = assimp_corners(path.string());
  expect_same(corners(m.vertices, m.triangles), want, path.string());
}

// STL, binary and ASCII (the library's own reader since it is installed: assimp is only the
// oracle now): the same triangles as assimp reads, three vertices each; malformed STL gets a
// line naming the problem.
TEST(Readers, StlAsAssimpReadsIt) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-2, 2);
  Corners want;
  for (int k = 0; k < 40; ++k) want.push_back({Vector3d(u(rng), u(rng), u(rng)), Vector3d(u(rng), u(rng), u(rng)),
                                              Vector3d(u(rng), u(rng), u(rng))});
  std::string binary(80, ' '), ascii = "solid test\n";
  const uint32_t n = uint32_t(want.size());
  binary.append(reinterpret_cast<const char*>(&n), 4);
  char number[80];
  for (const auto& t : want) {
    const float zero[3] = {0, 0, 0};
    binary.append(reinterpret_cast<const char*>(zero), 12);
    ascii += "  facet normal 0 0 0\n    outer loop\n";
    for (const auto& x : t) {
      const float f[3] = {float(x.x()), float(x.y()), float(x.z())};
      binary.append(reinterpret_cast<const char*>(f), 12);
      std::snprintf(number, sizeof number, "%.17g %.17g %.17g", f[0], f[1], f[2]);  // (the floats exactly)
      ascii += std::string("      vertex ") + number + "\n";
    }
    binary.append(2, '\0');
    ascii += "    endloop\n  endfacet\n";
  }
  ascii += "endsolid test\n";
  for (const auto& [name, text] : {std::pair{"b.stl", binary}, std::pair{"a.stl", ascii}}) {
    const std::string path = write_text(name, text);
    tools::Mesh m;
    std::string error;
    ASSERT_TRUE(tools::read_mesh(path, m, error)) << error;
    EXPECT_EQ(m.vertices.size(), 3 * want.size()) << name;
    expect_same(corners(m.vertices, m.triangles), want, name);
    expect_same(assimp_corners(path), want, std::string(name) + " (assimp)", 1e-6);
  }
  const std::string facet = "facet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n";
  const struct {
    const char* name;
    std::string text;
    const char* message;
  } cases[] = {
      {"open.stl", "solid x\n" + facet, ": the file ends without \"endsolid\""},
      {"nan.stl", "solid x\nfacet normal 0 0 0\nouter loop\nvertex 0 nan 0\n", ":4: a vertex needs three finite"},
      {"two.stl", "solid x\nfacet normal 0 0 0\nouter loop\nvertex 0 0 0\nendloop\n", ":5: expected \"vertex\""},
      {"after.stl", "solid x\n" + facet + "endsolid x\nsolid y\n", ":10: more data after \"endsolid\""},
      {"binary_nan.stl", binary.substr(0, 84 + 12) + std::string("\xff\xff\xff\x7f", 4) + binary.substr(100),
       ": triangle 0: a coordinate is NaN or Inf"},
  };
  for (const auto& c : cases) {
    tools::Mesh m;
    std::string error;
    const std::string path = write_text(c.name, c.text);
    EXPECT_FALSE(tools::read_mesh(path, m, error)) << c.name;
    EXPECT_NE(error.find(c.message), std::string::npos) << c.name << ": got \"" << error << "\"";
  }
}

// Each kind of malformed file, and the start of the message it gets.
TEST(Readers, MalformedFilesGetAClearError) {
  const std::string cube_v = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
  const std::string ply_head =
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n";
  const struct {
    const char* name;
    std::string text;
    const char* message;
  } cases[] = {
      {"index.off", "OFF\n4 1 0\n" + cube_v + "3 0 1 4\n", ":7: face 0: vertex index 4 is out of range [0, 4)"},
      {"negative.off", "OFF\n4 1 0\n" + cube_v + "3 0 -1 2\n", ":7: face 0: vertex index -1"},
      {"count.off", "OFF\n4 1 0\n" + cube_v + "12 0 1 2\n", ":7: a face starts with its vertex count"},
      {"short_face.off", "OFF\n4 1 0\n" + cube_v + "3 0 1\n", ":7: a face needs 3 vertex indices"},
      {"no_faces.off", "OFF\n4 2 0\n" + cube_v + "3 0 1 2\n", ":7: file ends before all faces"},
      {"extra.off", "OFF\n4 1 0\n" + cube_v + "3 0 1 2\n0 0 0\n", ":8: more data after the last face"},
      {"float_index.off", "OFF\n4 1 0\n" + cube_v + "3 0 1 2.5\n", ":7: a face needs 3 vertex indices"},
      {"huge_count.off", "OFF\n1000000000 0 0\n", ":2: bad vertex and face counts"},
      {"zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", ":4: bad face vertex \"0\""},
      {"range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", ":4: face 0: vertex index 3 is out of range [0, 3)"},
      {"relative.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n", ":4: face 0: vertex index -1 is out of range"},
      {"word.obj", "v 0 0 0\nf a b c\n", ":2: bad face vertex \"a\""},
      {"nan.obj", "v 0 nan 0\n", ":1: a vertex needs three finite coordinates"},
      {"index.ply",
       ply_head + "element face 1\nproperty list uchar int vertex_indices\nend_header\n" + cube_v + "3 0 1 9\n",
       ":14: face 0: vertex index 9 is out of range [0, 4)"},
      {"float_index.ply",
       ply_head + "element face 1\nproperty list uchar float vertex_indices\nend_header\n" + cube_v + "3 0 1 2.5\n",
       ":14: face 0: a vertex index must be an integer"},
      {"list_count.ply",
       ply_head + "element face 1\nproperty list uchar int vertex_indices\nend_header\n" + cube_v + "-3 0 1 2\n",
       ":14: face 0: bad list count"},
      {"no_list.ply", ply_head + "element face 1\nproperty int vertex_indices\nend_header\n" + cube_v + "3\n",
       ":9: the face element has no vertex_indices list"},
      {"missing_z.ply",
       "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n0 0\n",
       ":6: the vertex element needs one x, y and z each"},
      {"short.ply", ply_head + "end_header\n0 0 0\n1 0 0\n", ":9: file ends before all vertex elements"},
      {"extra_value.ply", ply_head + "end_header\n0 0 0 5\n", ":8: more values than the vertex element's properties"},
      {"extra_line.ply", ply_head + "end_header\n" + cube_v + "1 1 1\n", ":12: more data after the last element"},
      {"inf.ply", ply_head + "end_header\n0 0 0\n1 0 inf\n", ":9: vertex 1: z is not finite"},
      {"format.ply", "ply\nformat binary_middle_endian 1.0\n", ":2: unknown PLY format \"binary_middle_endian\""},
      {"type.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\n", ":4: bad property line"},
      {"binary_short.ply",
       "ply\nformat binary_little_endian 1.0\n" + ply_head.substr(ply_head.find("element")) + "end_header\n\x01\x02",
       ": vertex 0: missing or malformed x"},
      {"garbage.stl", "this is not an STL file", ": not an STL file"},
      {"empty.off", "", ": empty file"},
      {"unknown.xyz", "hello\n", ":1: expected three finite numbers"},
  };
  for (const auto& c : cases) {
    tools::Mesh m;
    std::string error;
    const std::string path = write_text(c.name, c.text);
    EXPECT_FALSE(tools::read_mesh(path, m, error)) << c.name;
    EXPECT_EQ(error.rfind(path, 0), 0u) << c.name << ": " << error;
    EXPECT_NE(error.find(c.message), std::string::npos)
        << c.name << ": got \"" << error << "\", want \"" << c.message << "\"";
  }
}

// Found by fuzzing (it crashed assimp 5.2.5, which then read OFF files): one vertex, and a face
// of twelve that indexes vertex 80.
TEST(Readers, FuzzFindingOffFaceOutOfRange) {
  const std::string text = "OFF\n1 2 80\n0 0 0\n12 80\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n0 0 1\n";
  tools::Mesh m;
  std::string error;
  EXPECT_FALSE(tools::read_mesh(write_text("fuzz.off", text), m, error));
  EXPECT_NE(error.find("a face starts with its vertex count"), std::string::npos) << error;
}

// The writer writes a whole sum and refuses, writing nothing, what is no mesh: an empty sum (a
// failed call's; it wrote "OFF 0 0 0" and said true), one without loops (SumParts::Planes: a
// segmentation fault, and an empty file), and a rounded one unless asked for its core.
TEST(Readers, TheWriterRefusesWhatIsNoMesh) {
  ConvexShape box, ball;
  ASSERT_EQ(shape_from_box(Box{}, box), Status::Ok);
  ASSERT_EQ(shape_from_sphere(1, ball), Status::Ok);
  const Eigen::Isometry3d id = Eigen::Isometry3d::Identity();
  const std::string path = testing::TempDir() + "minksum_writer.off";
  std::remove(path.c_str());
  std::string error;
  MinkowskiSum planes, rounded;
  ASSERT_EQ(minkowski_sum(box, id, box, id, planes, SumParts::Planes), Status::Ok);
  EXPECT_FALSE(write_mesh(path, planes, error));
  EXPECT_NE(error.find("no facet loops"), std::string::npos) << error;
  EXPECT_FALSE(write_mesh(path, MinkowskiSum{}, error));
  EXPECT_NE(error.find("empty"), std::string::npos) << error;
  ASSERT_EQ(minkowski_sum(box, id, ball, id, rounded), Status::Ok);
  EXPECT_FALSE(write_mesh(path, rounded, error));
  EXPECT_NE(error.find("core"), std::string::npos) << error;
  EXPECT_FALSE(std::ifstream(path).good());  // (nothing written)
  ASSERT_TRUE(write_mesh(path, rounded, error, true)) << error;
  std::vector<Eigen::Vector3d> read;
  ASSERT_TRUE(read_points(path, read, error)) << error;
  EXPECT_EQ(read.size(), 8u);  // the cube (the ball's core is its centre)
  std::remove(path.c_str());
}

}  // namespace
}  // namespace minksum
