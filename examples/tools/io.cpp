#include "io.hpp"

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>

namespace minksum::tools {

using Eigen::Vector3d;

namespace {

std::string lower_extension(const std::string& path) {
  const auto dot = path.find_last_of('.'), slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && slash > dot)) return "";
  std::string e = path.substr(dot + 1);
  for (char& c : e) c = char(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

// A line reader that counts lines, skips blank lines and strips '#' comments.
struct Lines {
  std::istream& in;
  int number = 0;
  bool next(std::string& line) {
    while (std::getline(in, line)) {
      ++number;
      const auto hash = line.find('#');
      if (hash != std::string::npos) line.erase(hash);
      if (line.find_first_not_of(" \t\r") != std::string::npos) return true;
    }
    return false;
  }
};

// Parses exactly `n` finite numbers from the start of `s` (more tokens are allowed if `rest`).
bool parse_numbers(const std::string& s, int n, double* out, bool rest) {
  std::istringstream ss(s);
  for (int k = 0; k < n; ++k) {
    std::string tok;
    if (!(ss >> tok)) return false;
    char* end = nullptr;
    out[k] = std::strtod(tok.c_str(), &end);
    if (end == tok.c_str() || *end != '\0' || !std::isfinite(out[k])) return false;
  }
  std::string extra;
  return rest || !(ss >> extra);
}

struct Reader {
  const std::string& path;
  std::string& error;
  bool fail(int line, const std::string& what) {
    error = path + (line > 0 ? ":" + std::to_string(line) : "") + ": " + what;
    return false;
  }
};

bool read_plain(std::istream& in, Reader r, std::vector<Vector3d>& pts) {
  Lines lines{in};
  std::string line;
  while (lines.next(line)) {
    double v[3];
    if (!parse_numbers(line, 3, v, false))
      return r.fail(lines.number, "expected three finite numbers \"x y z\"");
    pts.emplace_back(v[0], v[1], v[2]);
  }
  return true;
}

bool read_obj(std::istream& in, Reader r, std::vector<Vector3d>& pts) {
  Lines lines{in};
  std::string line;
  while (lines.next(line)) {
    std::istringstream ss(line);
    std::string tag;
    ss >> tag;
    if (tag != "v") continue;  // faces, normals, groups: not needed for a vertex set
    double v[3];
    std::string rest;
    std::getline(ss, rest);
    if (!parse_numbers(rest, 3, v, true))
      return r.fail(lines.number, "a vertex needs three finite coordinates");
    pts.emplace_back(v[0], v[1], v[2]);
  }
  return true;
}

bool read_off(std::istream& in, Reader r, std::vector<Vector3d>& pts) {
  Lines lines{in};
  std::string line;
  if (!lines.next(line)) return r.fail(0, "empty file");
  std::istringstream head(line);
  std::string magic;
  head >> magic;
  if (magic != "OFF") return r.fail(lines.number, "expected the OFF header");
  std::string counts;
  std::getline(head, counts);
  if (counts.find_first_not_of(" \t\r") == std::string::npos && !lines.next(counts))
    return r.fail(lines.number, "missing vertex and face counts");
  long nv = -1, nf = -1;
  std::istringstream cs(counts);
  if (!(cs >> nv >> nf) || nv < 0 || nf < 0 || nv > 100000000)
    return r.fail(lines.number, "bad vertex and face counts");
  for (long k = 0; k < nv; ++k) {
    double v[3];
    if (!lines.next(line)) return r.fail(lines.number, "file ends before all vertices are read");
    if (!parse_numbers(line, 3, v, true))
      return r.fail(lines.number, "a vertex needs three finite coordinates");
    pts.emplace_back(v[0], v[1], v[2]);
  }
  return true;
}

// PLY: the vertex element's x, y, z, in ASCII or binary little-endian.
bool read_ply(std::istream& in, Reader r, std::vector<Vector3d>& pts) {
  std::string line;
  int number = 0;
  auto next = [&]() { return bool(std::getline(in, line)) && (++number, true); };
  if (!next() || line.rfind("ply", 0) != 0) return r.fail(1, "expected the ply header");
  std::string format;
  long nv = -1;
  bool in_vertex = false, vertex_first = false, seen_element = false;
  std::vector<std::string> types;  // of the vertex element's properties
  int ix = -1, iy = -1, iz = -1;
  while (true) {
    if (!next()) return r.fail(number, "header has no end_header");
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream ss(line);
    std::string key;
    ss >> key;
    if (key == "end_header") break;
    if (key == "format") ss >> format;
    if (key == "element") {
      std::string name;
      long count = -1;
      ss >> name >> count;
      in_vertex = name == "vertex";
      if (in_vertex) {
        if (count < 0 || count > 100000000) return r.fail(number, "bad vertex count");
        nv = count;
        vertex_first = !seen_element;
      }
      seen_element = true;
    }
    if (key == "property" && in_vertex) {
      std::string type, name;
      ss >> type >> name;
      if (type == "list") return r.fail(number, "list properties on vertices are not supported");
      if (name == "x") ix = int(types.size());
      if (name == "y") iy = int(types.size());
      if (name == "z") iz = int(types.size());
      types.push_back(type);
    }
  }
  if (nv < 0 || ix < 0 || iy < 0 || iz < 0) return r.fail(number, "no vertex element with x, y, z");
  if (!vertex_first) return r.fail(number, "the vertex element must come first");
  if (format == "ascii") {
    for (long k = 0; k < nv; ++k) {
      if (!next()) return r.fail(number, "file ends before all vertices are read");
      std::vector<double> v(types.size());
      if (!parse_numbers(line, int(types.size()), v.data(), true))
        return r.fail(number, "a vertex needs " + std::to_string(types.size()) + " finite numbers");
      pts.emplace_back(v[ix], v[iy], v[iz]);
    }
    return true;
  }
  if (format != "binary_little_endian") return r.fail(number, "unsupported PLY format " + format);
  for (long k = 0; k < nv; ++k) {
    double v[3] = {0, 0, 0};
    for (size_t p = 0; p < types.size(); ++p) {
      const std::string& t = types[p];
      unsigned char buf[8];
      const int size = (t == "double" || t == "float64") ? 8
                       : (t == "float" || t == "float32" || t == "int" || t == "int32" ||
                          t == "uint" || t == "uint32") ? 4
                       : (t == "short" || t == "int16" || t == "ushort" || t == "uint16") ? 2
                       : (t == "char" || t == "int8" || t == "uchar" || t == "uint8") ? 1 : 0;
      if (size == 0) return r.fail(0, "unknown PLY property type " + t);
      if (!in.read(reinterpret_cast<char*>(buf), size))
        return r.fail(0, "file ends before all vertices are read");
      const int axis = int(p) == ix ? 0 : int(p) == iy ? 1 : int(p) == iz ? 2 : -1;
      if (axis < 0) continue;
      if (size == 8) {
        std::memcpy(&v[axis], buf, 8);
      } else if (t == "float" || t == "float32") {
        float f;
        std::memcpy(&f, buf, 4);
        v[axis] = f;
      } else {
        return r.fail(0, "coordinates must be float or double");
      }
      if (!std::isfinite(v[axis])) return r.fail(0, "vertex " + std::to_string(k) + " is not finite");
    }
    pts.emplace_back(v[0], v[1], v[2]);
  }
  return true;
}

}  // namespace

bool read_points(const std::string& path, std::vector<Vector3d>& points, std::string& error) {
  points.clear();
  std::ifstream in(path, std::ios::binary);
  Reader r{path, error};
  if (!in) return r.fail(0, "cannot open file");
  std::string ext = lower_extension(path);
  if (ext != "off" && ext != "obj" && ext != "ply") {  // sniff the content instead
    std::string first;
    in >> first;
    in.seekg(0);
    ext = first == "OFF" ? "off" : first == "ply" ? "ply" : "txt";
  }
  const bool ok = ext == "off"   ? read_off(in, r, points)
                  : ext == "obj" ? read_obj(in, r, points)
                  : ext == "ply" ? read_ply(in, r, points)
                                 : read_plain(in, r, points);
  if (ok && points.empty()) return r.fail(0, "no vertices");
  return ok;
}

bool write_mesh(const std::string& path, const MinkowskiSum& sum, std::string& error) {
  const std::string ext = lower_extension(path);
  if (ext != "off" && ext != "obj" && ext != "ply") {
    error = path + ": unknown mesh extension (use .off, .obj or .ply)";
    return false;
  }
  std::ofstream out(path);
  if (!out) {
    error = path + ": cannot write file";
    return false;
  }
  out.precision(17);
  const size_t V = sum.vertices.size(), F = sum.facets.size();
  if (ext == "off") out << "OFF\n" << V << ' ' << F << " 0\n";
  if (ext == "ply")
    out << "ply\nformat ascii 1.0\nelement vertex " << V
        << "\nproperty double x\nproperty double y\nproperty double z\nelement face " << F
        << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const auto& v : sum.vertices)
    out << (ext == "obj" ? "v " : "") << v.point.x() << ' ' << v.point.y() << ' ' << v.point.z()
        << '\n';
  for (const auto& f : sum.facets) {
    out << (ext == "obj" ? "f" : std::to_string(f.size()));
    for (int k : f) out << ' ' << (ext == "obj" ? k + 1 : k);
    out << '\n';
  }
  if (!out) {
    error = path + ": write failed";
    return false;
  }
  return true;
}

}  // namespace minksum::tools
