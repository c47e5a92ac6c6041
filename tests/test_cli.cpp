// The minksum command-line program, run as a user would: JSON output against CGAL's exact hull
// of the pairwise sums, the file formats, and bad input (exit code 2, one line with file:line).
#include <gtest/gtest.h>

#include <cstdio>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <algorithm>
#include <regex>
#include <unistd.h>
#include <sstream>
#include <sys/resource.h>
#include <sys/wait.h>

#include <minksum/kernels.hpp>

#include "checks.hpp"
#include <minksum/io.hpp>
#include "support/shapes.hpp"

namespace minksum {
namespace {

using Eigen::Vector3d;
namespace fs = std::filesystem;

struct CliRun {
  int code;
  std::string out, err;
};

fs::path scratch() {
  const fs::path dir = fs::temp_directory_path() / ("minksum_cli_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Runs the CLI with extra environment assignments (e.g. "MINKSUM_ISA=avx2"): this tree's, or
// the one MINKSUM_CLI_UNDER_TEST names (another build's, to see a test fail on older code).
CliRun run_env(const std::string& env, const std::string& args) {
  const fs::path dir = scratch();
  const char* other = std::getenv("MINKSUM_CLI_UNDER_TEST");
  const std::string cmd = "env " + env + " " + std::string(other ? other : MINKSUM_CLI) + " " + args + " > " +
                          (dir / "out").string() + " 2> " + (dir / "err").string();
  const int status = std::system(cmd.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(dir / "out"), slurp(dir / "err")};
}

CliRun run(const std::string& args) { return run_env("", args); }

std::string write(const std::string& name, const std::string& text) {
  const fs::path p = scratch() / name;
  std::ofstream(p) << text;
  return p.string();
}

// The same points in each of the four formats the CLI reads.
std::string write_points(const std::string& name, const std::vector<Vector3d>& pts, int format) {
  std::ostringstream s;
  s.precision(17);
  const char* ext[] = {".txt", ".off", ".obj", ".ply"};
  if (format == 1) s << "OFF\n" << pts.size() << " 0 0\n";
  if (format == 3)
    s << "ply\nformat ascii 1.0\nelement vertex " << pts.size()
      << "\nproperty float confidence\nproperty double x\nproperty double y\nproperty double z\n"
         "end_header\n";
  if (format == 0) s << "# plain text, one point per line\n";
  for (const auto& p : pts)
    s << (format == 2 ? "v " : format == 3 ? "0.5 " : "") << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
  return write(name + ext[format], s.str());
}

struct JsonPlane {
  Vector3d n;
  double d;
  int i, j;
};

std::vector<JsonPlane> parse_planes(const std::string& json) {
  std::vector<JsonPlane> out;
  const std::regex plane(R"(\[([-+0-9.eE]+), ([-+0-9.eE]+), ([-+0-9.eE]+), ([-+0-9.eE]+), (\d+), (\d+)\])");
  for (std::sregex_iterator it(json.begin(), json.end(), plane), end; it != end; ++it)
    out.push_back({Vector3d(std::stod((*it)[1]), std::stod((*it)[2]), std::stod((*it)[3])), std::stod((*it)[4]),
                   std::stoi((*it)[5]), std::stoi((*it)[6])});
  return out;
}

// Planes from the CLI's JSON are the facets of CGAL's exact hull of the pairwise sums a + s b:
// as many, each one an exact facet's plane, and every pair (i, j) an index of the files' points
// on its plane.
void expect_exact_planes(const std::vector<JsonPlane>& planes, const std::vector<Vector3d>& a,
                         const std::vector<Vector3d>& b, double s, double tol) {
  const auto hull = test::exact_hull(a, b, s);
  EXPECT_EQ(planes.size(), hull.size());
  for (const auto& p : planes) {
    bool twin = false;
    for (const auto& h : hull) twin = twin || ((p.n - h.normal).norm() < tol && std::abs(p.d - h.offset) < tol);
    EXPECT_TRUE(twin) << "plane " << p.n.transpose() << " is not an exact facet";
    ASSERT_LT(p.i, int(a.size()));
    ASSERT_LT(p.j, int(b.size()));
    EXPECT_NEAR(p.n.dot(a[p.i] + s * b[p.j]), p.d, tol);
  }
}

// The sum's JSON (from points a and b; s = -1 for the difference): a solid whose planes are the
// exact hull's, and the facet count it states.
void expect_exact_sum(const std::string& json, const std::vector<Vector3d>& a, const std::vector<Vector3d>& b,
                      double s) {
  EXPECT_NE(json.find("\"euler_ok\": true"), std::string::npos) << json;
  const auto planes = parse_planes(json);
  EXPECT_NE(json.find("\"facets\": " + std::to_string(planes.size())), std::string::npos);
  expect_exact_planes(planes, a, b, s, 1e-9);
}

TEST(Cli, SumJsonAgreesWithTheExactHullOnTheTable1Pairs) {
  int format = 0;
  for (const auto& pair : tools::table1_pairs()) {
    SCOPED_TRACE(pair.name);
    for (const char* diff : {"", " --diff"}) {
      const std::string a = write_points(pair.name + "_a", pair.a, format++ % 4);
      const std::string b = write_points(pair.name + "_b", pair.b, format++ % 4);
      const CliRun r = run("sum " + a + " " + b + " --json" + diff);
      ASSERT_EQ(r.code, 0) << r.err;
      EXPECT_EQ(r.err, "");
      expect_exact_sum(r.out, pair.a, pair.b, *diff ? -1 : 1);
    }
  }
}

TEST(Cli, WritesTheSumAsAMesh) {
  const auto pair = tools::table1_pairs()[0];
  const std::string a = write_points("ma", pair.a, 0), b = write_points("mb", pair.b, 0);
  for (const char* ext : {"off", "obj", "ply"}) {
    const std::string out = (scratch() / (std::string("m.") + ext)).string();
    const CliRun r = run("sum " + a + " " + b + " --out " + out);
    ASSERT_EQ(r.code, 0) << r.err;
    std::vector<Vector3d> pts;
    std::string error;
    ASSERT_TRUE(read_points(out, pts, error)) << error;
    EXPECT_EQ(pts.size(), 32u) << ext;
  }
}

// One bad input: exit code 2, nothing on stdout, exactly one line on stderr containing `what`.
void expect_rejected(const std::string& args, const std::string& what) {
  const CliRun r = run(args);
  EXPECT_EQ(r.code, 2) << args;
  EXPECT_EQ(r.out, "") << args;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find(what), std::string::npos) << "stderr: " << r.err;
}

// --pose-b places B (read in its body frame) by a unit quaternion and a translation: every
// method's planes are the exact hull's facets of the pairwise sums with B moved here, indices are the
// files', and query gives the distance of the explicitly moved file.
TEST(Cli, PoseBPlacesTheSecondOperand) {
  const auto pair = tools::table1_pairs()[2];
  const Eigen::Quaterniond q(Eigen::AngleAxisd(0.9, Vector3d(1, -2, 0.5).normalized()));
  const Vector3d t(30, -20, 45);
  std::ostringstream pose;
  pose.precision(17);
  pose << "\"" << q.w() << ' ' << q.x() << ' ' << q.y() << ' ' << q.z() << ' ' << t.x() << ' ' << t.y() << ' ' << t.z()
       << "\"";
  std::vector<Vector3d> moved;
  for (const auto& p : pair.b) moved.push_back(q * p + t);
  const std::string a = write_points("pa", pair.a, 0), b = write_points("pb", pair.b, 1),
                    bm = write_points("pbm", moved, 0);
  for (const char* method : {"fast", "reference", "hull"}) {
    SCOPED_TRACE(method);
    const CliRun r = run("sum " + a + " " + b + " --pose-b " + pose.str() + " --json --method " + method);
    ASSERT_EQ(r.code, 0) << r.err;
    // (The hull method's is the exact hull of the sums as doubles: here they round.)
    if (std::string(method) != "hull" || test::sums_are_doubles(pair.a, moved, 1))
      expect_exact_planes(parse_planes(r.out), pair.a, moved, 1, 1e-9);
  }
  const CliRun posed = run("query " + a + " " + b + " --pose-b " + pose.str() + " --json");
  const CliRun explicit_ = run("query " + a + " " + bm + " --json");
  ASSERT_EQ(posed.code, 0) << posed.err;
  ASSERT_EQ(explicit_.code, 0) << explicit_.err;
  const std::regex distance(R"("distance": ([-+0-9.eE]+))");
  std::smatch m1, m2;
  ASSERT_TRUE(std::regex_search(posed.out, m1, distance));
  ASSERT_TRUE(std::regex_search(explicit_.out, m2, distance));
  EXPECT_GT(std::stod(m2[1]), 1);  // separated: a real distance to compare
  EXPECT_NEAR(std::stod(m1[1]), std::stod(m2[1]), 1e-9);
  expect_rejected("sum " + a + " " + b + " --pose-b \"2 0 0 0 0 0 0\"", "unit length");
  expect_rejected("sum " + a + " " + b + " --pose-b \"1 0 0 0 0 0\"", "7 numbers");
  expect_rejected("query --box \"0 0 0 1 1 1 1 0 0 0\" --box \"3 0 0 1 1 1 1 0 0 0\" --pose-b \"1 0 0 0 0 0 0\"",
                  "vertex files");
}

TEST(Cli, BadInputGetsExitCodeTwoAndOneLine) {
  const std::string cube = write_points("cube", tools::cube_points(), 0);
  const std::string nan = write("nan.txt", "0 0 0\n1 0 0\nnan 1 0\n0 0 1\n");
  expect_rejected("sum " + nan + " " + cube, "nan.txt:3:");
  const std::string inf = write("inf.off", "OFF\n4 0 0\n0 0 0\n1 0 0\n0 1e999 0\n0 0 1\n");
  expect_rejected("sum " + cube + " " + inf, "inf.off:5:");
  const std::string shortoff = write("short.off", "OFF\n8 0 0\n0 0 0\n1 0 0\n");
  expect_rejected("sum " + shortoff + " " + cube, "short.off:4: file ends");
  const std::string junk = write("junk.txt", "0 0 0\n1 0 zero\n");
  expect_rejected("sum " + junk + " " + cube, "junk.txt:2:");
  const std::string ply = write("bad.ply", "ply\nformat ascii 1.0\nelement vertex 2\nend_header\n");
  expect_rejected("sum " + ply + " " + cube, "bad.ply");
  const std::string segment = write("segment.txt", "0 0 0\n1 1 1\n2 2 2\n");
  expect_rejected("sum " + segment + " " + cube, "collinear");
  const std::string dup = write("dup.txt", "1 2 3\n1 2 3\n1 2 3\n");
  expect_rejected("sum " + dup + " " + cube, "fewer than 3 distinct points");
  const std::string empty = write("empty.txt", "# nothing\n");
  expect_rejected("sum " + empty + " " + cube, "no vertices");
  expect_rejected("sum " + cube + " /nonexistent/file.off", "cannot open");
  const std::string t1 = write("t1.txt", "0 0 0\n1 0 0\n0 1 0\n");
  const std::string t2 = write("t2.txt", "2 0 0\n3 1 0\n2 2 0\n");
  expect_rejected("sum " + t1 + " " + t2, "flat");
  expect_rejected("sum " + cube, "two vertex files");
  expect_rejected("sum " + cube + " " + cube + " --method magic", "unknown method");
  expect_rejected("sum " + cube + " " + cube + " --frobnicate", "unknown option");
  expect_rejected("frobnicate", "unknown command");
  expect_rejected("sum " + cube + " " + cube + " --out " + (scratch() / "m.stl").string(), "extension");
}

std::string cube_off(const std::string& name, const std::string& bad_vertex, int bad_index);

// Each line names the flag or the file and the real problem (issue "Trust, part 2"): sizes
// out of double's range either way, a directory, a pose out of range, a negative margin, a plot
// path that cannot be written (checked before the run), extra words, and a run of no tick.
TEST(Cli, MessagesNameTheFlagOrFileAndTheRealProblem) {
  const std::string cube = write_points("mcube", tools::cube_points(), 0);
  const std::string tiny = write("tiny.txt", "0 0 0\n1e-200 0 0\n0 1e-200 0\n0 0 1e-200\n");
  expect_rejected("sum " + tiny + " " + cube, "tiny.txt: the shape is under 1e-100 across");
  const std::string span = write("span.txt", "0 0 -2\n0 2.77555756e-17 0\n1 1 0\n-1 0 0\n0 2.36610437e-271 -1\n");
  expect_rejected("sum " + span + " " + cube, "span.txt: its coordinates span more than 2^300");
  expect_rejected("sum " + scratch().string() + " " + cube, ": is a directory, not a file");
  expect_rejected("distance " + cube_off("dcube.off", "", -1) + " " + scratch().string(), ": is a directory, not a file");
  expect_rejected("query " + cube + " " + cube + " --pose-b \"1 0 0 0 1e300 0 0\"",
                  "--pose-b: the translation 1.0000000000000001e+300 exceeds the 1e100");
  expect_rejected("sum " + cube + " " + cube + " --pose-b \"1 0 0 0 0 0 -2e100\"", "--pose-b: the translation");
  expect_rejected("query " + cube + " " + cube + " --patch -1", "--patch: the margin -1 is negative");
  expect_rejected("haptics --seconds 1 --plot /nonexistent/x.png", "--plot /nonexistent/x.png: cannot write");
  expect_rejected("haptics --seconds 1 --trace /nonexistent/x.csv", "--trace /nonexistent/x.csv: cannot write");
  expect_rejected("haptics --seconds 0.0001", "less than one tick");
  expect_rejected("haptics --seconds 0.4 --rate 1", "less than one tick");
  expect_rejected("haptics --seconds 1 --rate 0.01", "--rate: 0.01 Hz is outside [1, 100000] Hz");
  expect_rejected("demo extra", "demo takes no arguments ('extra' given)");
  expect_rejected("--version extra", "--version takes no arguments ('extra' given)");
  // A tetrahedron of edge 1e80 is within the documented range (1e100): it is summed.
  const std::string huge = write("huge.txt", "0 0 0\n1e80 0 0\n0 1e80 0\n0 0 1e80\n");
  const CliRun big = run("sum " + huge + " " + huge);
  EXPECT_EQ(big.code, 0) << big.err;
  EXPECT_NE(big.out.find("V=4 E=6 F=4, Euler holds"), std::string::npos) << big.out;
  // --help after a command prints the help.
  for (const char* args : {"sum --help", "query -h", "haptics --seconds 1 --help"}) {
    const CliRun r = run(args);
    EXPECT_EQ(r.code, 0) << args;
    EXPECT_NE(r.out.find("usage: minksum"), std::string::npos) << args;
  }
}

TEST(Cli, HelpListsTheCommands) {
  const CliRun r = run("--help");
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("sum A B"), std::string::npos);
  EXPECT_NE(r.out.find("demo"), std::string::npos);
}

TEST(Cli, VersionPrintsTheIsasAndMinksumIsaForcesOne) {
  const CliRun plain = run("--version");
  ASSERT_EQ(plain.code, 0);
  EXPECT_NE(plain.out.find("compiled ISAs: scalar sse4_2 avx2 avx512"), std::string::npos);
  EXPECT_NE(plain.out.find(std::string("active ISA: ") + to_string(active_isa())), std::string::npos);
  for (Isa isa : {Isa::Scalar, Isa::Sse4_2, Isa::Avx2, Isa::Avx512}) {
    if (!isa_supported(isa)) continue;
    const CliRun forced = run_env(std::string("MINKSUM_ISA=") + to_string(isa), "--version");
    ASSERT_EQ(forced.code, 0);
    EXPECT_NE(forced.out.find(std::string("active ISA: ") + to_string(isa) + "\n"), std::string::npos) << forced.out;
  }
  // An unknown value is ignored: the best supported ISA stays active.
  const CliRun bogus = run_env("MINKSUM_ISA=altivec", "--version");
  EXPECT_NE(bogus.out.find(std::string("active ISA: ") + to_string(active_isa())), std::string::npos);
}

TEST(Cli, QueryJsonAgreesWithTheLibrary) {
  // Two boxes inline (centre, half extents, unit quaternion) and the same boxes as vertex files.
  const CliRun r = run("query --box \"0 0 0 1 1 1 1 0 0 0\" --box \"3 0.5 0.25 1 0.5 1 1 0 0 0\" --json");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("\"intersecting\": false"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"distance\": 1,"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"penetration_depth\": 0,"), std::string::npos) << r.out;
  std::vector<Vector3d> a = tools::cube_points(), b;
  for (const auto& p : tools::cube_points()) b.push_back(Vector3d(3, 0.5, 0.25) + p.cwiseProduct(Vector3d(1, 0.5, 1)));
  const CliRun f = run("query " + write_points("qa", a, 1) + " " + write_points("qb", b, 3) + " --json");
  ASSERT_EQ(f.code, 0) << f.err;
  EXPECT_NE(f.out.find("\"distance\": 1,"), std::string::npos) << f.out;
  const CliRun o = run("query --box \"0 0 0 1 1 1 1 0 0 0\" --box \"1.5 0 0 1 1 1 1 0 0 0\" --json");
  ASSERT_EQ(o.code, 0) << o.err;
  EXPECT_NE(o.out.find("\"intersecting\": true"), std::string::npos) << o.out;
  EXPECT_NE(o.out.find("\"penetration_depth\": 0.5,"), std::string::npos) << o.out;
  EXPECT_NE(o.out.find("\"penetration_direction\": [1, 0, 0]"), std::string::npos) << o.out;
}

// --patch: the contact patch in the JSON line. B's bottom face, 0.4 above A's top, over x in
// [0, 1], y in [-0.5, 0.5], lies within A's top face: the patch is that square on A's plane.
TEST(Cli, QueryPrintsTheContactPatch) {
  const std::string boxes = "query --box \"0 0 0 1 1 1 1 0 0 0\" --box \"0.5 0 1.9 0.5 0.5 0.5 1 0 0 0\"";
  const CliRun r = run(boxes + " --patch 0.5 --json");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::size_t at = r.out.find("\"points\": [");
  ASSERT_NE(at, std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"feature_a\": {\"face\": "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"normal\": [0, 0, 1]"), std::string::npos) << r.out;
  const std::string list = r.out.substr(at, r.out.find("]]", at) + 2 - at);
  const std::regex point(R"(\[([-0-9.e]+), ([-0-9.e]+), ([-0-9.e]+)\])");
  std::vector<Vector3d> got;
  for (auto it = std::sregex_iterator(list.begin(), list.end(), point); it != std::sregex_iterator(); ++it)
    got.push_back(Vector3d(std::stod((*it)[1]), std::stod((*it)[2]), std::stod((*it)[3])));
  ASSERT_EQ(got.size(), 4u) << r.out;
  for (const Vector3d& corner :
       {Vector3d(0, -0.5, 1), Vector3d(1, -0.5, 1), Vector3d(1, 0.5, 1), Vector3d(0, 0.5, 1)}) {
    double nearest = HUGE_VAL;
    for (const auto& x : got) nearest = std::min(nearest, (x - corner).norm());
    EXPECT_LT(nearest, 1e-12) << r.out;
  }
  const CliRun beyond = run(boxes + " --patch 0.3 --json");  // 0.4 apart: no patch
  ASSERT_EQ(beyond.code, 0) << beyond.err;
  EXPECT_NE(beyond.out.find("\"points\": []"), std::string::npos) << beyond.out;
  expect_rejected(boxes + " --patch -0.1", "margin");
  expect_rejected(boxes + " --patch", "needs a value");
}

TEST(Cli, QueryRejectsBadInput) {
  expect_rejected("query --box \"0 0 0 1 1 1 1 0 0 0\" --box \"1 2 3\"", "10 numbers");
  expect_rejected("query --box \"0 0 0 1 1 1 1 0 0 0\" --box \"0 0 nan 1 1 1 1 0 0 0\"", "NaN");
  expect_rejected("query --box \"0 0 0 1 1 1 1 0 0 0\" --box \"0 0 0 1 1 1 2 0 0 0\"", "unit length");
  expect_rejected("query --box \"0 0 0 1 1 1 1 0 0 0\" --box \"0 0 0 1 0 1 1 0 0 0\"", "invalid box");
  expect_rejected("query --box \"0 0 0 1 1 1 1 0 0 0\"", "two --box");
  const std::string nan = write("qnan.txt", "0 0 0\n1 0 0\nnan 1 0\n0 0 1\n");
  const std::string cube = write_points("qcube", tools::cube_points(), 0);
  expect_rejected("query " + nan + " " + cube, "qnan.txt:3:");
}

// The unit cube [0, 1]^3 as 12 triangles (OFF), with an optional bad coordinate or index.
std::string cube_off(const std::string& name, const std::string& bad_vertex = "", int bad_index = -1) {
  std::string text = "OFF\n8 12 0\n";
  for (int k = 0; k < 8; ++k)
    text += (k == 7 && !bad_vertex.empty())
                ? bad_vertex + "\n"
                : std::to_string(k & 1) + " " + std::to_string(k >> 1 & 1) + " " + std::to_string(k >> 2 & 1) + "\n";
  const int f[12][3] = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                        {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  for (int k = 0; k < 12; ++k)
    text += "3 " + std::to_string(f[k][0]) + " " + std::to_string(f[k][1]) + " " +
            std::to_string(k == 11 && bad_index >= 0 ? bad_index : f[k][2]) + "\n";
  return write(name, text);
}

TEST(Cli, DistanceBetweenMeshes) {
  const std::string a = cube_off("ca.off"), b = cube_off("cb.off");
  // B turned 90 degrees about z (it then spans x in [-1, 0]) and moved by 3 along x: gap 1.
  const std::string pose = "--pose \"0.70710678118654757 0 0 0.70710678118654757 3 0.5 0\"";
  for (const std::string mode : {"", " --brute"}) {
    const CliRun r = run("distance " + a + " " + b + " " + pose + " --json" + mode);
    ASSERT_EQ(r.code, 0) << r.err;
    std::smatch m;
    ASSERT_TRUE(std::regex_search(r.out, m, std::regex("\"distance\": ([0-9.e+-]+),"))) << r.out;
    EXPECT_NEAR(std::stod(m[1]), 1, 1e-12) << r.out;
  }
  const std::string poses = write("poses.txt", "# three poses\n1 0 0 0 3 0 0\n1 0 0 0 0.5 0 0\n1 0 0 0 0 0 5\n");
  const CliRun r = run("distance " + a + " " + b + " --poses " + poses);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 3) << r.out;
  EXPECT_NE(r.out.find("\"distance\": 2,"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"distance\": 0,"), std::string::npos) << r.out;  // overlapping
  EXPECT_NE(r.out.find("\"distance\": 4,"), std::string::npos) << r.out;
  const CliRun demo = run("distance");  // the bunnies, or a fallback mesh: it says which
  ASSERT_EQ(demo.code, 0) << demo.err;
  EXPECT_NE(demo.out.find("demo: two copies of "), std::string::npos) << demo.out;
  EXPECT_NE(demo.out.find("culled"), std::string::npos) << demo.out;
}

std::vector<double> field(const std::string& out, const std::string& key);

// Files of vertices without faces (XYZ text, PLY) are point clouds: the closest pair of points,
// and a cloud against a mesh, as all pairs give them.
TEST(Cli, DistanceBetweenPointClouds) {
  const std::string xyz = write("cloud.xyz", "0 0 0\n1 0 0\n1 0 0\n0 1 0\n");  // a duplicate point
  const std::string ply = write("cloud.ply",
                                "ply\nformat ascii 1.0\nelement vertex 2\nproperty double x\n"
                                "property double y\nproperty double z\nend_header\n0 0 3\n0.25 0 5\n");
  // B moved by (1, 0, -1): its points at (1, 0, 2) and (1.25, 0, 4); the nearest is (1, 0, 0), 2 away.
  for (const std::string mode : {"", " --brute"}) {
    const CliRun r = run("distance " + xyz + " " + ply + " --pose \"1 0 0 0 1 0 -1\" --json" + mode);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(field(r.out, "distance"), std::vector<double>{2}) << r.out;
  }
  const CliRun human = run("distance " + xyz + " " + ply);
  ASSERT_EQ(human.code, 0) << human.err;
  EXPECT_NE(human.out.find("4 points and 2 points"), std::string::npos) << human.out;
  // Without a pose the files are taken as given: a cloud that shares a point with it is 0 away.
  const std::string shared = write("cloud_shared.xyz", "5 5 5\n0 1 0\n");
  for (const std::string mode : {"", " --brute"}) {
    const CliRun given = run("distance " + xyz + " " + shared + " --json" + mode);
    ASSERT_EQ(given.code, 0) << given.err;
    EXPECT_EQ(field(given.out, "distance"), std::vector<double>{0}) << given.out;
  }
  // A cloud against a mesh (the cube [-1, 1]^3 of cube_off): the point (1, 0, 2) is 1 above it.
  const CliRun mesh = run("distance " + cube_off("cloud_cube.off") + " " + ply + " --pose \"1 0 0 0 1 0 -1\" --json");
  ASSERT_EQ(mesh.code, 0) << mesh.err;
  EXPECT_NEAR(field(mesh.out, "distance").at(0), 1, 1e-15) << mesh.out;
  expect_rejected("distance " + xyz + " " + write("cloud_nan.xyz", "0 0 0\n1 nan 0\n"), "cloud_nan.xyz:2:");
  expect_rejected("distance " + xyz + " " +
                      write("cloud_empty.ply",
                            "ply\nformat ascii 1.0\nelement vertex 0\nproperty double x\n"
                            "property double y\nproperty double z\nend_header\n"),
                  "no vertices");
}

TEST(Cli, DistanceRejectsBadInput) {
  const std::string a = cube_off("da.off");
  expect_rejected("distance " + a + " " + cube_off("dnan.off", "nan 0 1"), "dnan.off:10:");  // file:line
  expect_rejected("distance " + a + " " + cube_off("dindex.off", "", 99), "dindex.off");
  expect_rejected("distance " + a + " " + write("garbage.off", "OFF\n3 1 0\n0 0\n"), "garbage.off");
  expect_rejected("distance " + a + " " + a + " --pose \"1 0 0 0 1 2\"", "7 numbers");
  expect_rejected("distance " + a + " " + a + " --pose \"2 0 0 0 1 2 3\"", "unit length");
  expect_rejected("distance " + a + " " + a + " --poses " + write("bad_poses.txt", "1 0 0 0 0 0 0\n1 0 0 x 0 0 0\n"),
                  "bad_poses.txt:2:");
  expect_rejected("distance " + a, "two mesh files");
}

// Numbers after `key` in each JSON line of `out`.
std::vector<double> field(const std::string& out, const std::string& key);

// The 6-DOF haptic loop from the command line: a fast plunge of the default tool (a sphere)
// onto the thin sheet is felt (ticks in contact, times of impact swept), nothing allocated; bad
// options, tools and files get exit code 2.
TEST(Cli, HapticsPlungesOntoTheSheet) {
  const CliRun r = run("haptics --scene sheet --speed 10 --press 5 --seconds 0.3 --json");
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_EQ(field(r.out, "contacts").size(), 1u) << r.out;
  EXPECT_GT(field(r.out, "contacts")[0], 250) << r.out;
  EXPECT_GT(field(r.out, "sweeps")[0], 250) << r.out;
  EXPECT_LE(field(r.out, "allocations")[0], 0) << r.out;  // 0, or -1 where not counted
  expect_rejected("haptics --speed -1", "--speed");
  expect_rejected("haptics --press nan", "--press");
  expect_rejected("haptics --tool no_such_tool.off", "no_such_tool.off");
  expect_rejected("haptics --tool sphere:-1", "the radius must lie in");
  expect_rejected("haptics --tool capsule:1", "expected capsule:H:R in mm");
  expect_rejected("haptics --tool sphere:5:3", "expected sphere:R in mm");
  expect_rejected("haptics --scene " + write("empty.off", "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n"), "empty.off");
}

// What a new user met (issue "Trust, part 3"): a rounded sum written with --core (refused
// without it, saying how), a rate no clock can keep, a tool file of points alone (its hull, as
// documented), a count of one number, the distance's default pose as the help states it, and
// a back-to-back run that counts the ticks longer than the period.
TEST(Cli, WhatANewUserMet) {
  const std::string cube = write("core_cube.xyz", "0 0 0\n1 0 0\n0 1 0\n1 1 0\n0 0 1\n1 0 1\n0 1 1\n1 1 1\n");
  const std::string out = (scratch() / "core.off").string();
  expect_rejected("sum sphere:0.5 " + cube + " --out " + out, "add --core to write its core");
  EXPECT_FALSE(fs::exists(out));
  CliRun r = run("sum sphere:0.5 " + cube + " --out " + out + " --core");
  EXPECT_EQ(r.code, 0) << r.err;
  std::vector<Vector3d> written;
  std::string error;
  EXPECT_TRUE(read_points(out, written, error) && written.size() == 8u) << error;  // the cube, moved by the centre
  expect_rejected("sum " + cube + " " + cube + " --core", "--core needs --out");
  expect_rejected("haptics --rate 1e9", "--rate: 1e9 Hz is outside [1, 100000] Hz");
  expect_rejected("query sphere:1:2 sphere:1", "sphere:R needs 1 number (R), got 2");
  expect_rejected("query capsule:1 sphere:1", "capsule:H:R needs 2 numbers (H R), got 1");
  // A tool file of vertices alone (a tetrahedron's corners): the hull of its points.
  const std::string tet = write("tet.xyz", "0 0 0\n1 0 0\n0 1 0\n0 0 1\n");
  r = run("haptics --tool " + tet + " --seconds 0.1 --json");
  EXPECT_EQ(r.code, 0) << r.err;
  // The help says what distance does with two files and no pose: they are used as given.
  r = run("--help");
  EXPECT_NE(r.out.find("(default: the files as given)"), std::string::npos) << r.out;
  const std::string a = cube_off("given_a.off"), b = cube_off("given_b.off");
  r = run("distance " + a + " " + b + " --json");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(field(r.out, "distance"), std::vector<double>{0}) << r.out;  // the same cube, where it is
  // Back to back there are no deadlines; the ticks longer than the period are counted (a
  // 10 us period: a tick that sweeps takes longer).
  r = run("haptics --scene sheet --speed 10 --press 5 --seconds 0.3 --rate 100000 --json");
  ASSERT_EQ(r.code, 0) << r.err;
  ASSERT_EQ(field(r.out, "max_us").size(), 2u) << r.out;  // (coherent, then cold)
  EXPECT_EQ(field(r.out, "misses")[0] > 0, field(r.out, "max_us")[0] > 10) << r.out;
}

// A haptic run's memory does not grow with its length: ten times the ticks, the same peak
// (each tick kept about 440 bytes before: 40 MB more here, and 1e8 ticks ran out of memory).
TEST(Cli, HapticMemoryIsFixedWhateverTheRunsLength) {
  const auto peak_kb = [] {
    rusage u{};
    getrusage(RUSAGE_CHILDREN, &u);
    return u.ru_maxrss;  // (the largest child so far: the short run first)
  };
  CliRun r = run("haptics --scene sheet --seconds 5 --json");
  ASSERT_EQ(r.code, 0) << r.err;
  const long short_run = peak_kb();
  r = run("haptics --scene sheet --seconds 50 --json");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(field(r.out, "ticks"), std::vector<double>{50000}) << r.out;
  EXPECT_LT(peak_kb() - short_run, 8 * 1024) << "KB: " << short_run << " then " << peak_kb();
}

// Numbers after `key` in each JSON line of `out`.
std::vector<double> field(const std::string& out, const std::string& key) {
  std::vector<double> v;
  const std::regex re("\"" + key + "\": ([-0-9.e+]+)");
  for (auto it = std::sregex_iterator(out.begin(), out.end(), re); it != std::sregex_iterator(); ++it)
    v.push_back(std::stod((*it)[1]));
  return v;
}

// --coherent along a pose sequence (in, out of contact, and a jump back) prints the answers
// printed without it, for both commands; it needs --poses.
TEST(Cli, CoherentPosesGiveTheSameAnswers) {
  std::string text;
  for (int k = 0; k < 200; ++k) {
    const double angle = 0.004 * k, x = k == 150 ? 3.0 : 3.0 - 0.02 * k;  // tick 150 jumps back
    text += std::to_string(std::cos(angle / 2)) + " 0 " + std::to_string(std::sin(angle / 2)) + " 0 " +
            std::to_string(x) + " 0.3 0.1\n";
  }
  const std::string poses = write("trajectory.txt", text);
  const std::string a = write_points("co_a", tools::icosahedron_points(), 1);
  const std::string b = write_points("co_b", tools::dodecahedron_points(), 1);
  const CliRun cold = run("query " + a + " " + b + " --poses " + poses);
  const CliRun warm = run("query " + a + " " + b + " --poses " + poses + " --coherent");
  ASSERT_EQ(cold.code, 0) << cold.err;
  ASSERT_EQ(warm.code, 0) << warm.err;
  for (const std::string key : {"distance", "penetration_depth", "max_distance"}) {
    const auto c = field(cold.out, key), w = field(warm.out, key);
    ASSERT_EQ(c.size(), 200u) << key;
    ASSERT_EQ(w.size(), c.size()) << key;
    for (size_t k = 0; k < c.size(); ++k) EXPECT_NEAR(w[k], c[k], 1e-12 * std::max(1.0, c[k])) << key << " " << k;
    if (key == std::string("max_distance"))  // (the CLI prints every field: the farthest pair too)
      for (size_t k = 0; k < c.size(); ++k) EXPECT_GT(c[k], 2.0) << k;
  }
  const std::regex touching("\"intersecting\": (true|false)");
  std::vector<std::string> cold_verdicts, warm_verdicts;
  for (auto it = std::sregex_iterator(cold.out.begin(), cold.out.end(), touching); it != std::sregex_iterator(); ++it)
    cold_verdicts.push_back((*it)[1]);
  for (auto it = std::sregex_iterator(warm.out.begin(), warm.out.end(), touching); it != std::sregex_iterator(); ++it)
    warm_verdicts.push_back((*it)[1]);
  EXPECT_EQ(warm_verdicts, cold_verdicts);
  const auto depth = field(cold.out, "penetration_depth");
  EXPECT_GT(std::count_if(depth.begin(), depth.end(), [](double d) { return d > 0; }), 10);  // contact too
  const std::string ca = cube_off("coa.off"), cb = cube_off("cob.off");
  const CliRun mesh_cold = run("distance " + ca + " " + cb + " --poses " + poses);
  const CliRun mesh_warm = run("distance " + ca + " " + cb + " --poses " + poses + " --coherent");
  ASSERT_EQ(mesh_cold.code, 0) << mesh_cold.err;
  ASSERT_EQ(mesh_warm.code, 0) << mesh_warm.err;
  const auto c = field(mesh_cold.out, "distance"), w = field(mesh_warm.out, "distance");
  ASSERT_EQ(c.size(), 200u);
  EXPECT_EQ(w, c);  // the seeded search ends on the same triangle distance
  expect_rejected("query " + a + " " + b + " --coherent", "--coherent needs --poses");
  expect_rejected("distance " + ca + " " + cb + " --coherent", "--coherent needs --poses");
  expect_rejected("query " + a + " " + b + " --poses " + write("bad_traj.txt", "1 0 0 0 0 0\n"), "bad_traj.txt:1:");
}

// A triangle (a flat operand) with a cube: the solid prism-like sum, the exact hull's facets.
TEST(Cli, FlatOperandGivesASolidSum) {
  const std::vector<Vector3d> tri = {{0.1, 0.2, 0.3}, {1.1, -0.4, 0.5}, {0.3, 0.9, -0.7}};
  const std::string file = write("tri.txt", "0.1 0.2 0.3\n1.1 -0.4 0.5\n0.3 0.9 -0.7\n");
  const std::string cube = write_points("cube2", tools::cube_points(), 1);
  const CliRun r = run("sum " + cube + " " + file + " --json");
  ASSERT_EQ(r.code, 0) << r.err;
  expect_exact_sum(r.out, tools::cube_points(), tri, 1);
}

// --toi: B falls onto A through its poses, one JSON line per motion. Unit cubes (corners at
// +-1), B from 5 to 1 above A and then up again: the faces, 3 apart, meet at 3/4 of the first
// motion; the second moves apart from overlapping (time 0).
TEST(Cli, QueryPrintsTheTimeOfImpact) {
  const std::string a = write_points("toi_a", tools::cube_points(), 1);
  const std::string poses = write("toi_poses.txt", "1 0 0 0 0 0 5\n1 0 0 0 0 0 1\n1 0 0 0 0 0 9\n");
  const CliRun r = run("query " + a + " " + a + " --toi " + poses);
  ASSERT_EQ(r.code, 0) << r.err;
  const auto hit = field(r.out, "time");
  ASSERT_EQ(hit.size(), 2u) << r.out;
  EXPECT_NEAR(hit[0], 0.75, 1e-12) << r.out;
  EXPECT_EQ(hit[1], 0) << r.out;
  EXPECT_NE(r.out.find("\"motion\": 0, \"hit\": true"), std::string::npos) << r.out;
  expect_rejected("query " + a + " " + a + " --toi " + write("toi_one.txt", "1 0 0 0 0 0 5\n"), "two poses");
  expect_rejected("query " + a + " " + a + " --toi " + poses + " --patch 0.1", "--toi takes");
}

// Spheres, capsules and radii on the command line: closed forms, and bad specs refused in one
// line with exit code 2.
TEST(Cli, QueryTakesSpheresCapsulesAndRadii) {
  CliRun r = run("query sphere:0.5 sphere:0.25 --pose-b \"1 0 0 0 2 0 0\" --json");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto distance = [](const std::string& out) {
    const size_t at = out.find("\"distance\": ");
    return at == std::string::npos ? -1.0 : std::strtod(out.c_str() + at + 12, nullptr);
  };
  EXPECT_EQ(distance(r.out), 1.25) << r.out;
  // A unit cube's hull with a radius of 0.5 against a capsule lying 3 above along x.
  const std::string cube = write("cube.xyz", "0 0 0\n1 0 0\n0 1 0\n1 1 0\n0 0 1\n1 0 1\n0 1 1\n1 1 1\n");
  r = run("query " + cube + " capsule:2:0.25 --radius-a 0.5 --pose-b \"0.70710678118654757 0 0.70710678118654757 0 0.5 0.5 4\" --json");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NEAR(distance(r.out), 2.25, 1e-14) << r.out;  // 4 - 0.25 - (1 + 0.5)
  for (const std::string bad : {"sphere:-1 sphere:1", "sphere:0 sphere:1", "capsule:1 sphere:1", "sphere:x sphere:1",
                                "sphere:1e300 sphere:1", "capsule:-1:1 sphere:1", "sphere:1 sphere:1 --radius-b -2",
                                "sphere:1 sphere:1 --radius-a nan"}) {
    r = run("query " + bad);
    EXPECT_EQ(r.code, 2) << bad;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << bad << ": " << r.err;
  }
  // Cores that sum to less than a solid: swept by the radii they are solids (a ball of radius 3,
  // a capsule of radius 2).
  r = run("sum sphere:1 sphere:2 --json");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("\"vertices\": 1, \"facets\": 0, \"edges\": 0"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"radius\": 3,"), std::string::npos) << r.out;
  r = run("sum sphere:1 capsule:1:1");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("V=2 E=1 F=0"), std::string::npos) << r.out;
  // A rounded sum: the cores' sum and the radii added, printed; not a mesh to write, nor a
  // sum for the polytope methods.
  r = run("sum sphere:0.5 " + cube + " --radius-b 0.25 --json");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("\"radius\": 0.75"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"facets\": 6"), std::string::npos) << r.out;  // the cube translated
  r = run("sum " + cube + " sphere:0.5");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("swept by a ball of radius 0.5"), std::string::npos) << r.out;
  for (const std::string bad : {" --out " + (scratch() / "rounded.off").string(), std::string(" --method hull")}) {
    r = run("sum sphere:0.5 " + cube + bad);
    EXPECT_EQ(r.code, 2) << bad;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << bad << ": " << r.err;
  }
}

}  // namespace
}  // namespace minksum
