// minksum: command-line front end of the library (sum, query, distance, demo).
#include <minksum/minksum.hpp>

#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <sstream>
#include <cstdio>
#include <fstream>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include <minksum/io.hpp>
#include "support/shapes.hpp"

namespace minksum::cli {

int usage_error(const std::string& what) {
  std::fprintf(stderr, "minksum: %s (see minksum --help)\n", what.c_str());
  return 2;
}

bool parse_numbers(const std::string& text, const std::string& what, const std::string& layout, size_t count,
                   std::vector<double>& v, std::string& error) {
  std::istringstream in(text);
  v.clear();
  for (std::string token; in >> token;) {
    char* end = nullptr;
    v.push_back(std::strtod(token.c_str(), &end));
    if (*end != '\0') return error = what + ": '" + token + "' is not a number", false;
    if (!std::isfinite(v.back())) return error = what + ": a number is NaN or Inf", false;
  }
  if (v.size() != count)
    return error = what + " needs " + std::to_string(count) + (count == 1 ? " number (" : " numbers (") + layout +
                   "), got " + std::to_string(v.size()),
           false;
  return true;
}

bool unit_quaternion(const double* q, Eigen::Matrix3d& rotation, std::string& error) {
  const Eigen::Quaterniond quat(q[0], q[1], q[2], q[3]);
  if (std::abs(quat.norm() - 1) > 1e-6) return error = "the quaternion is not of unit length", false;
  rotation = quat.normalized().toRotationMatrix();
  return true;
}

bool parse_pose(const std::string& text, const std::string& what, Eigen::Isometry3d& pose, std::string& error) {
  std::vector<double> v;
  Eigen::Matrix3d rotation;
  if (!parse_numbers(text, what, "qw qx qy qz tx ty tz", 7, v, error)) return false;
  if (!unit_quaternion(&v[0], rotation, error)) return error = what + ": " + error, false;
  for (int k = 4; k < 7; ++k)
    if (!(std::abs(v[k]) <= kMaxCoordinate)) {
      char text[120];
      std::snprintf(text, sizeof text, ": the translation %.17g exceeds the 1e100 the library accepts", v[k]);
      return error = what + text, false;
    }
  pose = Eigen::Isometry3d::Identity();
  pose.linear() = rotation, pose.translation() = Eigen::Vector3d(v[4], v[5], v[6]);
  return true;
}

bool read_poses(const std::string& file, std::vector<Eigen::Isometry3d>& poses, std::string& error) {
  std::ifstream in(file);
  if (!in) return error = file + ": cannot open", false;
  int line_no = 0;
  for (std::string line; std::getline(in, line);) {
    ++line_no;
    if (line.find_first_not_of(" \t\r") == std::string::npos || line[0] == '#') continue;
    Eigen::Isometry3d p;
    if (!parse_pose(line, "pose", p, error)) return error = file + ":" + std::to_string(line_no) + ": " + error, false;
    poses.push_back(p);
  }
  if (poses.empty()) return error = file + ": no pose", false;
  return true;
}

}  // namespace minksum::cli

namespace {

using namespace minksum;

const char* kHelp =
    "usage: minksum <command> [options]\n"
    "\n"
    "commands:\n"
    "  sum A B [--pose-b \"qw qx qy qz tx ty tz\"] [--diff] [--method fast|reference|hull]\n"
    "          [--radius-a R] [--radius-b R] [--out M.off|M.obj|M.ply [--core]] [--json]\n"
    "      Minkowski sum of the convex hulls of the vertices in files A and B (OFF, OBJ, PLY\n"
    "      or plain text \"x y z\" per line), B placed by a rigid pose (unit quaternion, then\n"
    "      translation; default: as read); --diff computes A (-) B = A (+) (-B). The fast\n"
    "      method prepares both as shapes and applies the pose inside the sum. A may be\n"
    "      sphere:R, and --radius-a/--radius-b round A or B: the sum of rounded shapes is the sum\n"
    "      of their cores swept by a ball of the radii added (printed; --out writes the core with\n"
    "      --core, and refuses it without).\n"
    "  query A B [--pose-b \"qw qx qy qz tx ty tz\" | --poses FILE [--coherent]] [--patch MARGIN]\n"
    "          [--radius-a R] [--radius-b R] [--json]\n"
    "  query --box \"cx cy cz hx hy hz qw qx qy qz\" --box \"...\" [--patch MARGIN] [--json]\n"
    "  query A B --toi FILE\n"
    "      Collision, exact distance with closest points, maximum distance and penetration\n"
    "      depth and direction of two convex objects (vertex files, or boxes given inline:\n"
    "      centre, half extents, unit quaternion). --poses reads one pose of B per line and\n"
    "      prints one JSON line each; --coherent starts each query from the last answer (the\n"
    "      same answers, to 1e-12 relative). --patch adds the contact patch where the objects\n"
    "      overlap, touch or lie within MARGIN (>= 0): its normal, depth, the supporting\n"
    "      feature of each and the patch's corners. --toi reads poses of B (A stays) and prints,\n"
    "      per motion from one pose to the next, the time of impact as a JSON line. A or B may\n"
    "      be sphere:R or capsule:H:R (half length H along z) instead of a file; --radius-a and\n"
    "      --radius-b sweep a ball of radius R about A or B (a rounded shape).\n"
    "  distance [MESH_A MESH_B] [--pose \"qw qx qy qz tx ty tz\"] [--poses FILE [--coherent]]\n"
    "           [--json] [--brute]\n"
    "      Exact minimum distance between two triangle meshes (PLY, OBJ, OFF, STL) through\n"
    "      octrees; the pose places B in A's frame (default: the files as given);\n"
    "      --poses reads one pose per line and prints one JSON line each (--coherent:\n"
    "      each search seeded by the last answer, the same distances); --brute checks by all\n"
    "      pairs. No meshes: two bunnies (../shared/data beside the source tree, else a generated\n"
    "      mesh of the same size), the second shifted along +x by 1.1 x the first's width.\n"
    "  haptics [--tool sphere:R|capsule:H:R|box|icosa|MESH] [--scene MESH|bunny_full|bumpy_full|sheet]\n"
    "          [--seconds S] [--rate HZ] [--press MM] [--slide MM] [--speed M/S] [--realtime]\n"
    "          [--plot out.png] [--trace out.csv] [--json]\n"
    "      A 1 kHz 6-DOF haptic loop: a device approaches, presses MM (default 2) into and slides\n"
    "      (--tool: a sphere of radius R mm, the default sphere:5 as in CHAI3D; a capsule of half\n"
    "      length H and radius R mm along the tool's z; a box 20 x 16 x 12 mm; an icosahedron; or\n"
    "      MESH, the convex hull of its vertices centred and scaled to 30 mm across) turning\n"
    "      over the scene mesh, --slide MM (default 8) each way (0: turning in place; --speed:\n"
    "      plunges straight down at that speed); --rate within [1, 100000] Hz; a proxy\n"
    "      swept by time of impact stays out of the scene, and the contact patch at it gives\n"
    "      force and torque. Run twice on the same path: cold, then with each tick's mesh\n"
    "      distance seeded by the last tick's answer. Tick latency percentiles on the wall clock\n"
    "      and in thread CPU time over every tick, missed deadlines (--realtime paces the ticks;\n"
    "      late starts by the OS are counted apart from ticks whose own CPU time overran; back\n"
    "      to back, the ticks longer than the period), allocations and exceptions inside the\n"
    "      loop, contacts; --plot draws the run (gnuplot), --trace writes the times of the first\n"
    "      10,000 ticks (the run's memory is fixed, whatever its length).\n"
    "  demo\n"
    "      The paper's Table 1 pairs: V, E, F and the time of each path.\n"
    "  --version, --help\n"
    "\n"
    "exit codes: 0 success, 2 bad input or usage (one line on stderr)\n";

using cli::usage_error;

const char* method_name(Method m) {
  return m == Method::Fast ? "fast" : m == Method::Reference ? "reference" : m == Method::Hull ? "hull" : "kernel";
}

double now_us() {
  using namespace std::chrono;
  return duration<double, std::micro>(steady_clock::now().time_since_epoch()).count();
}

// Reads a vertex file into a prepared shape; prints a one-line error on failure.
// "sphere:R" or "capsule:H:R" (half length H along z, radius R) into a shape; false with a
// message if malformed or refused.
bool load_rounded(const std::string& spec, ConvexShape& p) {
  const bool sphere = spec.rfind("sphere:", 0) == 0;
  std::string numbers = spec.substr(spec.find(':') + 1);
  for (char& c : numbers) c = c == ':' ? ' ' : c;
  std::vector<double> v;
  std::string error;
  if (!cli::parse_numbers(numbers, sphere ? "sphere:R" : "capsule:H:R", sphere ? "R" : "H R", sphere ? 1 : 2, v,
                          error)) {
    std::fprintf(stderr, "minksum: %s\n", error.c_str());
    return false;
  }
  const Status s = sphere ? shape_from_sphere(v[0], p) : shape_from_capsule(v[0], v[1], p);
  if (s == Status::InvalidArgument)
    std::fprintf(stderr, "minksum: %s: the radius must be positive (and a half length not negative)\n", spec.c_str());
  else if (s != Status::Ok)
    std::fprintf(stderr, "minksum: %s: a radius or half length beyond 1e100 or under 1e-100\n", spec.c_str());
  return s == Status::Ok;
}

// An operand: "sphere:R", "capsule:H:R", or a vertex file (its convex hull).
bool load(const std::string& path, ConvexShape& p) {
  if (path.rfind("sphere:", 0) == 0 || path.rfind("capsule:", 0) == 0) return load_rounded(path, p);
  std::vector<Eigen::Vector3d> pts;
  std::string error;
  if (!read_points(path, pts, error)) {
    std::fprintf(stderr, "minksum: %s\n", error.c_str());
    return false;
  }
  const Status s = shape_from_points(pts, p);
  if (s != Status::Ok) {
    // OutOfRange within the coordinates' range: the shape too small, or its coordinates spanning
    // more than 2^300 (shape_from_points).
    bool large = false;
    Eigen::AlignedBox3d box;
    for (const auto& x : pts) large = large || !(x.cwiseAbs().maxCoeff() <= kMaxCoordinate), box.extend(x);
    if (s == Status::OutOfRange && !large && !(box.diagonal().norm() >= kMinExtent))
      std::fprintf(stderr, "minksum: %s: the shape is under 1e-100 across, too small for double precision\n",
                   path.c_str());
    else if (s == Status::OutOfRange && !large)
      std::fprintf(stderr,
                   "minksum: %s: its coordinates span more than 2^300 (a nonzero one under 5e-91 of the largest), "
                   "beyond the exact predicates' range\n",
                   path.c_str());
    else
      std::fprintf(stderr, "minksum: %s: %s\n", path.c_str(), to_string(s));
    return false;
  }
  return true;
}

// --radius-a R or --radius-b R at argv[k] into radius[0] or radius[1] (k moves past R).
bool radius_option(int argc, char** argv, int& k, double (&radius)[2], std::string& error) {
  const std::string a = argv[k];
  std::vector<double> v;
  if (k + 1 >= argc) return error = a + " needs a value", false;
  if (!cli::parse_numbers(argv[++k], a, "R", 1, v, error)) return false;
  if (!(v[0] >= 0)) return error = a + ": the radius " + std::string(argv[k]) + " is negative (it must be >= 0)", false;
  radius[a == "--radius-b"] = v[0];
  return true;
}

// The two operands of a sum or a query, each with its extra radius (--radius-a, --radius-b).
bool load_operands(const std::vector<std::string>& files, const double (&radius)[2], ConvexShape& a, ConvexShape& b) {
  ConvexShape* shapes[2] = {&a, &b};
  for (int k = 0; k < 2; ++k) {
    if (!load(files[size_t(k)], *shapes[k])) return false;
    if (radius[k] == 0) continue;
    if (const Status s = shape_with_radius(*shapes[k], radius[k], *shapes[k]); s != Status::Ok) {
      std::fprintf(stderr, "minksum: %s: %s\n", k ? "--radius-b" : "--radius-a", to_string(s));
      return false;
    }
  }
  return true;
}

// Parses "cx cy cz hx hy hz qw qx qy qz" into a box; false with a message if malformed.
bool parse_box(const std::string& text, Box& box, std::string& error) {
  std::vector<double> v;
  if (!cli::parse_numbers(text, "--box", "cx cy cz hx hy hz qw qx qy qz", 10, v, error)) return false;
  if (!cli::unit_quaternion(&v[6], box.rotation, error)) return error = "--box: " + error, false;
  box.center = Eigen::Vector3d(v[0], v[1], v[2]);
  box.half_extents = Eigen::Vector3d(v[3], v[4], v[5]);
  return true;
}

std::string vec(const Eigen::Vector3d& v) {
  char buf[100];
  std::snprintf(buf, sizeof buf, "[%.17g, %.17g, %.17g]", v.x(), v.y(), v.z());
  return buf;
}

// A patch feature as JSON ({"face": 3}, {"edge": [2, 5]}, {"vertex": 7}, null) or words.
std::string feature(const ContactPatch::Feature& f, bool json) {
  using Kind = ContactPatch::Feature::Kind;
  const std::string i0 = std::to_string(f.index[0]), i1 = std::to_string(f.index[1]);
  switch (f.kind) {
    case Kind::Face:
      return json ? "{\"face\": " + i0 + "}" : "face " + i0;
    case Kind::Edge:
      return json ? "{\"edge\": [" + i0 + ", " + i1 + "]}" : "edge " + i0 + "-" + i1;
    case Kind::Vertex:
      return json ? "{\"vertex\": " + i0 + "}" : "vertex " + i0;
    case Kind::None:
      break;
  }
  return json ? "null" : "vertices of nearly coplanar faces";
}

// The contact patch: a JSON member (`, "patch": {...}`) or lines of text.
std::string patch_text(const ContactPatch& c, bool json) {
  std::string points;
  for (int k = 0; k < c.size; ++k) points += (json ? (k ? ", " : "") : "\n  ") + vec(c.points[k]);
  char head[300];
  if (json) {
    std::snprintf(head, sizeof head, ", \"patch\": {\"normal\": %s, \"depth\": %.17g, ", vec(c.normal).c_str(),
                  c.depth);
    return head + ("\"feature_a\": " + feature(c.feature_a, true) + ", \"feature_b\": " + feature(c.feature_b, true) +
                   ", \"points\": [" + points + "]}");
  }
  if (c.size == 0) return "patch: none (farther apart than the margin)\n";
  std::snprintf(head, sizeof head, "patch: %d point%s along %s, depth %.17g, A's %s on B's %s:", c.size,
                c.size == 1 ? "" : "s", vec(c.normal).c_str(), c.depth, feature(c.feature_a, false).c_str(),
                feature(c.feature_b, false).c_str());
  return head + points + "\n";
}

// One query's answer, as one JSON line or a sentence; with its contact patch if given.
void print_answer(const Proximity& p, bool json, const ContactPatch* patch = nullptr) {
  if (json) {
    std::printf(
        "{\"intersecting\": %s, \"distance\": %.17g, \"closest_points\": [%s, %s], "
        "\"max_distance\": %.17g, \"penetration_depth\": %.17g, "
        "\"penetration_direction\": %s%s}\n",
        p.intersecting ? "true" : "false", p.distance, vec(p.point_a).c_str(), vec(p.point_b).c_str(), p.max_distance,
        p.penetration_depth, vec(p.penetration_direction).c_str(), patch ? patch_text(*patch, true).c_str() : "");
    return;
  }
  if (p.intersecting) {
    std::printf("intersecting: penetration depth %.17g along %s; max distance %.17g\n", p.penetration_depth,
                vec(p.penetration_direction).c_str(), p.max_distance);
  } else {
    std::printf("separated: distance %.17g between %s and %s; max distance %.17g\n", p.distance, vec(p.point_a).c_str(),
                vec(p.point_b).c_str(), p.max_distance);
  }
  if (patch) std::printf("%s", patch_text(*patch, false).c_str());
}

// query A B --toi FILE: B moves through the file's poses, A stays; one JSON line per motion.
int query_toi(const ConvexShape& A, const ConvexShape& B, const std::vector<Eigen::Isometry3d>& poses) {
  const Eigen::Isometry3d identity = Eigen::Isometry3d::Identity();
  for (std::size_t k = 0; k + 1 < poses.size(); ++k) {
    TimeOfImpact toi;
    if (const Status s = time_of_impact(A, identity, identity, B, poses[k], poses[k + 1], toi); s != Status::Ok) {
      std::fprintf(stderr, "minksum: motion %zu: %s\n", k, to_string(s));
      return 2;
    }
    std::printf(
        "{\"motion\": %zu, \"hit\": %s, \"time\": %.17g, \"distance\": %.17g, \"normal\": %s, "
        "\"closest_points\": [%s, %s], \"tolerance\": %.17g, \"converged\": %s, \"iterations\": %d}\n",
        k, toi.hit ? "true" : "false", toi.time, toi.distance, vec(toi.normal).c_str(), vec(toi.point_a).c_str(),
        vec(toi.point_b).c_str(), toi.tolerance, toi.converged ? "true" : "false", toi.iterations);
  }
  return 0;
}

int cmd_query(int argc, char** argv) {
  std::vector<std::string> files, boxes;
  bool json = false, posed = false, coherent = false, with_patch = false;
  double margin = 0, radius[2] = {0, 0};
  Eigen::Isometry3d pose_b = Eigen::Isometry3d::Identity();
  std::vector<Eigen::Isometry3d> poses, motion;
  std::string error;
  for (int k = 0; k < argc; ++k) {
    const std::string a = argv[k];
    if (a == "--toi") {
      if (k + 1 >= argc) return usage_error("--toi needs a value");
      if (!cli::read_poses(argv[++k], motion, error)) return usage_error(error);
      if (motion.size() < 2) return usage_error("--toi needs two poses or more");
    } else if (a == "--json") {
      json = true;
    } else if (a == "--coherent") {
      coherent = true;
    } else if (a == "--pose-b") {
      if (k + 1 >= argc) return usage_error("--pose-b needs a value");
      if (!cli::parse_pose(argv[++k], "--pose-b", pose_b, error)) return usage_error(error);
      posed = true;
    } else if (a == "--poses") {
      if (k + 1 >= argc) return usage_error("--poses needs a value");
      if (!cli::read_poses(argv[++k], poses, error)) return usage_error(error);
    } else if (a == "--box") {
      if (k + 1 >= argc) return usage_error("--box needs a value");
      boxes.push_back(argv[++k]);
    } else if (a == "--radius-a" || a == "--radius-b") {
      if (!radius_option(argc, argv, k, radius, error)) return usage_error(error);
    } else if (a == "--patch") {
      std::vector<double> v;
      if (k + 1 >= argc) return usage_error("--patch needs a value");
      if (!cli::parse_numbers(argv[++k], "--patch", "margin", 1, v, error)) return usage_error(error);
      if (!(v[0] >= 0)) return usage_error("--patch: the margin " + std::string(argv[k]) + " is negative (it must be >= 0)");
      with_patch = true, margin = v[0];
    } else if (a.rfind("--", 0) == 0) {
      return usage_error("unknown option '" + a + "'");
    } else {
      files.push_back(a);
    }
  }
  if (posed && !poses.empty()) return usage_error("give --pose-b or --poses, not both");
  if (coherent && poses.empty()) return usage_error("--coherent needs --poses");
  if (!motion.empty()) {
    if (posed || !poses.empty() || with_patch || !boxes.empty() || files.size() != 2)
      return usage_error("--toi takes two vertex files, without --pose-b, --poses, --patch or --box");
    ConvexShape A, B;
    if (!load_operands(files, radius, A, B)) return 2;
    return query_toi(A, B, motion);
  }
  Proximity p;
  Status s;
  ConvexShape A, B;  // (the patch's operands: the files' shapes, or the boxes')
  static ContactPatch patch;
  const Eigen::Isometry3d identity = Eigen::Isometry3d::Identity();
  if (boxes.size() == 2 && files.empty()) {
    Box a, b;
    if (!parse_box(boxes[0], a, error) || !parse_box(boxes[1], b, error)) return usage_error(error);
    if (posed || !poses.empty()) return usage_error("--pose-b and --poses are for vertex files");
    if (radius[0] > 0 || radius[1] > 0) return usage_error("--radius-a and --radius-b are for vertex files and rounded shapes");
    s = proximity(a, b, p, Want::All);
    if (s == Status::Ok && with_patch && (s = shape_from_box(a, A)) == Status::Ok &&
        (s = shape_from_box(b, B)) == Status::Ok)
      s = contact_patch(A, identity, B, identity, margin, patch);
  } else if (files.size() == 2 && boxes.empty()) {
    if (!load_operands(files, radius, A, B)) return 2;
    if (!poses.empty()) {                 // one JSON line per pose; consecutive poses share one cache
      ProximityCache cache, patch_cache;  // (one per kind of query)
      for (const Eigen::Isometry3d& pose : poses) {
        s = coherent ? proximity(A, identity, B, pose, cache, p, Want::All)  // (the CLI prints every field)
                     : proximity(A, identity, B, pose, p, Want::All);
        if (s == Status::Ok && with_patch)
          s = coherent ? contact_patch(A, identity, B, pose, margin, patch_cache, patch)
                       : contact_patch(A, identity, B, pose, margin, patch);
        if (s != Status::Ok) {
          std::fprintf(stderr, "minksum: pose: %s\n", to_string(s));
          return 2;
        }
        print_answer(p, true, with_patch ? &patch : nullptr);
      }
      return 0;
    }
    s = proximity(A, identity, B, pose_b, p, Want::All);
    if (s == Status::Ok && with_patch) s = contact_patch(A, identity, B, pose_b, margin, patch);
  } else {
    return usage_error("query needs two vertex files or two --box");
  }
  if (s != Status::Ok) {
    std::fprintf(stderr, "minksum: %s\n", to_string(s));
    return 2;
  }
  print_answer(p, json, with_patch ? &patch : nullptr);
  return 0;
}

int cmd_sum(int argc, char** argv) {
  std::vector<std::string> files;
  bool diff = false, json = false, core = false;
  Method method = Method::Fast;
  std::string out_path, error;
  double radius[2] = {0, 0};
  Eigen::Isometry3d pose_b = Eigen::Isometry3d::Identity();
  for (int k = 0; k < argc; ++k) {
    const std::string a = argv[k];
    if (a == "--diff") {
      diff = true;
    } else if (a == "--core") {
      core = true;
    } else if (a == "--pose-b") {
      if (k + 1 >= argc) return usage_error("--pose-b needs a value");
      if (!cli::parse_pose(argv[++k], "--pose-b", pose_b, error)) return usage_error(error);
    } else if (a == "--json") {
      json = true;
    } else if (a == "--radius-a" || a == "--radius-b") {
      if (!radius_option(argc, argv, k, radius, error)) return usage_error(error);
    } else if (a == "--method" || a == "--out") {
      if (k + 1 >= argc) return usage_error(a + " needs a value");
      const std::string v = argv[++k];
      if (a == "--out") {
        out_path = v;
      } else if (v == "fast" || v == "reference" || v == "hull") {
        method = v == "fast" ? Method::Fast : v == "reference" ? Method::Reference : Method::Hull;
      } else {
        return usage_error("unknown method '" + v + "'");
      }
    } else if (a.rfind("--", 0) == 0) {
      return usage_error("unknown option '" + a + "'");
    } else {
      files.push_back(a);
    }
  }
  if (files.size() != 2) return usage_error("sum needs two vertex files");
  if (core && out_path.empty()) return usage_error("--core needs --out");
  ConvexShape SA, SB;
  if (!load_operands(files, radius, SA, SB)) return 2;
  const ConvexPolytope &A = SA.polytope(), &B = SB.polytope();
  const bool rounded = SA.radius() > 0 || SB.radius() > 0;
  if (rounded && method != Method::Fast)
    return usage_error(std::string("--method ") + method_name(method) +
                       " takes polytopes: a rounded operand (a sphere, a capsule, --radius-a/-b) takes the fast path");
  // The other methods take polytopes: B's hull moved by the pose (the same vertex order).
  ConvexPolytope moved_b;
  if (method != Method::Fast) {
    std::vector<Eigen::Vector3d> pts;
    for (const auto& v : B.vertices) pts.push_back(pose_b * v);
    if (const Status s = polytope_from_points(pts, moved_b); s != Status::Ok) {
      std::fprintf(stderr, "minksum: %s: %s\n", files[1].c_str(), to_string(s));
      return 2;
    }
  }
  const Eigen::Isometry3d identity = Eigen::Isometry3d::Identity();
  MinkowskiSum m;
  const double t0 = now_us();
  const Status s =
      method == Method::Fast
          ? (diff ? minkowski_difference(SA, identity, SB, pose_b, m) : minkowski_sum(SA, identity, SB, pose_b, m))
          : (diff ? minkowski_difference(A, moved_b, m, method) : minkowski_sum(A, moved_b, m, method));
  const double t1 = now_us();
  if (s != Status::Ok) {
    std::fprintf(stderr, "minksum: %s\n",
                 to_string(s));
    return 2;
  }
  if (!out_path.empty()) {
    std::string error;
    if (m.radius > 0 && !core) {
      std::fprintf(stderr, "minksum: --out: a rounded sum (radius %.17g) is not a polygon mesh; add --core to write its core\n",
                   m.radius);
      return 2;
    }
    if (!write_mesh(out_path, m, error, core)) {
      std::fprintf(stderr, "minksum: %s\n", error.c_str());
      return 2;
    }
  }
  if (json) {
    // %.17g round-trips every double; indices are mapped back to the files' vertex order.
    std::printf("{\"vertices\": %d, \"facets\": %d, \"edges\": %d, \"euler_ok\": %s, \"planes\": [", m.V, m.F, m.E,
                m.euler_ok ? "true" : "false");
    for (size_t k = 0; k < m.planes.size(); ++k) {
      const auto& p = m.planes[k];
      // (A sphere's core is its one point: index 0.)
      const auto input = [](const ConvexPolytope& x, int i) { return x.input_index.empty() ? i : x.input_index[size_t(i)]; };
      std::printf("%s[%.17g, %.17g, %.17g, %.17g, %d, %d]", k ? ", " : "", p.normal.x(), p.normal.y(), p.normal.z(),
                  p.offset, input(A, p.i), input(B, method == Method::Fast ? p.j : moved_b.input_index[size_t(p.j)]));
    }
    std::printf("], \"radius\": %.17g, \"method\": \"%s\", \"time_us\": %.17g}\n", m.radius, method_name(method),
                t1 - t0);
  } else {
    std::printf("%s %s %s: V=%d E=%d F=%d, Euler %s%s, %.1f us (%s path)\n", files[0].c_str(), diff ? "(-)" : "(+)",
                files[1].c_str(), m.V, m.E, m.F, m.euler_ok ? "holds" : "fails", m.corrected ? " (corrected)" : "",
                t1 - t0, method_name(m.method));
    if (m.radius > 0)
      std::printf("rounded: this %s swept by a ball of radius %.17g\n",
                  m.F > 0 ? (m.F == 2 ? "polygon" : "polytope") : m.V == 1 ? "point" : "segment", m.radius);
  }
  return 0;
}

// Median time of one call, over repetitions filling about `budget_us`.
template <class F>
double time_us(F&& f, double budget_us = 20000) {
  std::vector<double> t;
  const double start = now_us();
  while (t.size() < 5 || (now_us() - start < budget_us && t.size() < 100000)) {
    const double t0 = now_us();
    f();
    t.push_back(now_us() - t0);
  }
  std::nth_element(t.begin(), t.begin() + t.size() / 2, t.end());
  return t[t.size() / 2];
}

// Nanoseconds per sum of the Table 1 cube pair through the box-box kernel's whole-polytope
// path (box_box_sum), 32 lanes per call as a batch would use it, and whether it took the pair
// as one in general position.
template <class T>
double kernel_sum_ns(bool& general) {
  constexpr int N = 32, kCalls = 16;
  auto A = std::make_unique<BoxBatch<T, N>>(), B = std::make_unique<BoxBatch<T, N>>();
  auto out = std::make_unique<BoxBoxSum<T, N>>();
  tools::fill_table1_cubes(*A, *B);
  const double us = time_us([&] {
    for (int call = 0; call < kCalls; ++call) box_box_sum(*A, *B, *out);
  });
  general = out->general[0] == 1;
  return 1e3 * us / (kCalls * N);
}

int cmd_demo() {
  std::printf(
      "minksum demo: the paper's Table 1 (B rotated 0.7 rad about (1,2,3)),\n"
      "median time per full sum (planes, support pairs, vertices, facet loops) on this\n"
      "machine: prepared shapes (built once, B's rotation passed as its pose), the fast\n"
      "path on polytopes (prepared on every call), the reference path (the paper as\n"
      "written), and the hull method (the exact quickhull of the pairwise sums). The paper\n"
      "(2007): OSM 6.1-82.9 ms, CGAL quickhull 131-277 ms. Google Benchmark runs:\n"
      "build/bench/minksum_bench.\n\n");
  std::printf("%-14s %4s %4s %4s  %13s %10s %14s %10s  %13s\n", "pair", "V", "E", "F", "prepared [us]", "fast [us]",
              "reference [us]", "hull [us]", "hull/prepared");
  Eigen::Isometry3d pose_b = Eigen::Isometry3d::Identity();
  const Eigen::Isometry3d identity = Eigen::Isometry3d::Identity();
  double hull_cubes = 0;
  for (const auto& pair : tools::table1_pairs()) {
    ConvexPolytope A, B;
    ConvexShape SA, SB;
    if (polytope_from_points(pair.a, A) != Status::Ok || polytope_from_points(pair.b, B) != Status::Ok ||
        shape_from_points(pair.a, SA) != Status::Ok ||
        shape_from_points(pair.b_body, SB) != Status::Ok)
      return 1;
    pose_b.linear() = pair.rotation;
    MinkowskiSum m;
    double t[4];
    t[0] = time_us([&] { minkowski_sum(SA, identity, SB, pose_b, m); });
    const Method methods[3] = {Method::Fast, Method::Reference, Method::Hull};
    for (int k = 0; k < 3; ++k) t[k + 1] = time_us([&] { minkowski_sum(A, B, m, methods[k]); });
    minkowski_sum(SA, identity, SB, pose_b, m);
    std::printf("%-14s %4d %4d %4d  %13.2f %10.2f %14.2f %10.2f  %12.1fx\n", pair.name.c_str(), m.V, m.E, m.F, t[0],
                t[1], t[2], t[3], t[3] / t[0]);
    if (pair.name == "cube_rotcube") hull_cubes = t[3];
  }
  bool general_d = false, general_f = false;
  const double ns_d = kernel_sum_ns<double>(general_d), ns_f = kernel_sum_ns<float>(general_f);
  std::printf(
      "\ncube_rotcube through the box-box kernel (box_box_sum: planes, support pairs, vertex\n"
      "loops and corners; 32 pairs per call): %.1f ns per sum in double, %.1f ns in float;\n"
      "hull / kernel %.0fx and %.0fx%s\n",
      ns_d, ns_f, 1e3 * hull_cubes / ns_d, 1e3 * hull_cubes / ns_f,
      general_d && general_f ? "" : " (NOT in general position: the loops do not apply)");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) return usage_error("no command");
  const std::string cmd = argv[1];
  // --help anywhere (minksum sum --help) prints the help; demo, --version and --help take
  // nothing more.
  for (int k = 1; k < argc; ++k)
    if (!std::strcmp(argv[k], "--help") || !std::strcmp(argv[k], "-h")) {
      std::fputs(kHelp, stdout);
      return 0;
    }
  if ((cmd == "demo" || cmd == "--version" || cmd == "help") && argc > 2)
    return usage_error(cmd + " takes no arguments ('" + argv[2] + "' given)");
  if (cmd == "help") {
    std::fputs(kHelp, stdout);
    return 0;
  }
  if (cmd == "--version") {
    // Every ISA is compiled on x86-64; the active one is chosen once at start-up
    // (MINKSUM_ISA=scalar|sse4_2|avx2|avx512 forces one the CPU supports).
    std::printf("minksum " MINKSUM_VERSION_STRING "\ncompiled ISAs: scalar sse4_2 avx2 avx512\nsupported ISAs:");
    for (Isa isa : {Isa::Scalar, Isa::Sse4_2, Isa::Avx2, Isa::Avx512})
      if (isa_supported(isa)) std::printf(" %s", to_string(isa));
    std::printf("\nactive ISA: %s\n", to_string(active_isa()));
    return 0;
  }
  if (cmd == "sum") return cmd_sum(argc - 2, argv + 2);
  if (cmd == "query") return cmd_query(argc - 2, argv + 2);
  if (cmd == "distance") return cli::cmd_distance(argc - 2, argv + 2);
  if (cmd == "haptics") return cli::cmd_haptics(argc - 2, argv + 2);
  if (cmd == "demo") return cmd_demo();
  return usage_error("unknown command '" + cmd + "'");
}
