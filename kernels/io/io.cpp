// The strict file readers and the sum writer (minksum/io.hpp): every count, number and index
// checked, each error one line naming the file and its line.
#include <minksum/io.hpp>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace minksum {

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

// Parses a whole token as an integer (an index or a count).
bool parse_index(const std::string& tok, long& out) {
  char* end = nullptr;
  errno = 0;
  out = std::strtol(tok.c_str(), &end, 10);
  return end != tok.c_str() && *end == '\0' && errno == 0;
}

// The polygons read so far: vertex indices as written, checked once all vertices are known.
struct Faces {
  std::vector<long> index;  // all polygons' indices, one after the other
  std::vector<int> line;    // per polygon: the line it was on (0 in binary files)
  std::vector<size_t> start{0};
  void add(const std::vector<long>& polygon, int at) {
    index.insert(index.end(), polygon.begin(), polygon.end());
    line.push_back(at);
    start.push_back(index.size());
  }
  // Every index within [0, n); polygons fanned into triangles, points and lines dropped.
  bool finish(Reader r, size_t n, std::vector<std::array<int, 3>>* triangles) const {
    for (size_t f = 0; f + 1 < start.size(); ++f) {
      for (size_t k = start[f]; k < start[f + 1]; ++k)
        if (index[k] < 0 || size_t(index[k]) >= n)
          return r.fail(line[f], "face " + std::to_string(f) + ": vertex index " + std::to_string(index[k]) +
                                     " is out of range [0, " + std::to_string(n) + ")");
      if (triangles)
        for (size_t k = start[f] + 1; k + 1 < start[f + 1]; ++k)
          triangles->push_back({int(index[start[f]]), int(index[k]), int(index[k + 1])});
    }
    return true;
  }
};

// Counts in headers are bounded so that a corrupt count fails instead of exhausting memory.
constexpr long kMaxCount = 100000000;

bool read_plain(std::istream& in, Reader r, std::vector<Vector3d>& pts, Faces&) {
  Lines lines{in};
  std::string line;
  while (lines.next(line)) {
    double v[3];
    if (!parse_numbers(line, 3, v, false)) return r.fail(lines.number, "expected three finite numbers \"x y z\"");
    pts.emplace_back(v[0], v[1], v[2]);
  }
  return true;
}

// OBJ: "v x y z [w]" and "f i[/t][/n] ..." (1-based, or negative: relative to the last vertex);
// the other statements (normals, texture coordinates, groups, materials) are not needed.
bool read_obj(std::istream& in, Reader r, std::vector<Vector3d>& pts, Faces& faces) {
  Lines lines{in};
  std::string line;
  std::vector<long> polygon;
  while (lines.next(line)) {
    std::istringstream ss(line);
    std::string tag;
    ss >> tag;
    if (tag == "v") {
      double v[3];
      std::string rest;
      std::getline(ss, rest);
      if (!parse_numbers(rest, 3, v, true)) return r.fail(lines.number, "a vertex needs three finite coordinates");
      pts.emplace_back(v[0], v[1], v[2]);
    } else if (tag == "f") {
      polygon.clear();
      for (std::string tok; ss >> tok;) {
        long i = 0;
        if (!parse_index(tok.substr(0, tok.find('/')), i) || i == 0)
          return r.fail(lines.number, "bad face vertex \"" + tok + "\"");
        polygon.push_back(i > 0 ? i - 1 : long(pts.size()) + i);
      }
      faces.add(polygon, lines.number);
    }
  }
  return true;
}

// OFF: the header, the counts, the vertices, then "k i1 ... ik [colour]" per face.
bool read_off(std::istream& in, Reader r, std::vector<Vector3d>& pts, Faces& faces) {
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
  if (!(cs >> nv >> nf) || nv < 0 || nf < 0 || nv > kMaxCount || nf > kMaxCount)
    return r.fail(lines.number, "bad vertex and face counts");
  for (long k = 0; k < nv; ++k) {
    double v[3];
    if (!lines.next(line)) return r.fail(lines.number, "file ends before all vertices are read");
    if (!parse_numbers(line, 3, v, true)) return r.fail(lines.number, "a vertex needs three finite coordinates");
    pts.emplace_back(v[0], v[1], v[2]);
  }
  std::vector<long> polygon;
  for (long f = 0; f < nf; ++f) {
    if (!lines.next(line)) return r.fail(lines.number, "file ends before all faces are read");
    std::istringstream ss(line);
    std::string tok;
    long k = -1;
    if (!(ss >> tok) || !parse_index(tok, k) || k < 0 || k > std::min(nv, 1000000L))
      return r.fail(lines.number, "a face starts with its vertex count");
    polygon.assign(size_t(k), 0);
    for (long& i : polygon)
      if (!(ss >> tok) || !parse_index(tok, i))
        return r.fail(lines.number, "a face needs " + std::to_string(k) + " vertex indices");
    faces.add(polygon, lines.number);
  }
  if (lines.next(line)) return r.fail(lines.number, "more data after the last face");
  return true;
}

// PLY (Turk 1994; ASCII, binary little- or big-endian): every element is read so that the ones
// after it can be found; kept are the vertex element's x, y, z and the face element's
// vertex_indices (or vertex_index) lists.
struct PlyProperty {
  std::string name;
  int type = 0;        // bytes of a scalar, or of a list's items; negative: floating point
  int count_type = 0;  // bytes of a list's count; 0 for a scalar
  bool is_signed = false;
};

struct PlyElement {
  std::string name;
  long count = 0;
  std::vector<PlyProperty> properties;
  int axis[3] = {-1, -1, -1};  // the vertex element's x, y, z properties
  int indices = -1;            // the face element's vertex_indices property
};

// Bytes of a PLY type (negative for float and double), or 0 if unknown.
int ply_type(const std::string& t, bool& is_signed) {
  is_signed = t == "char" || t == "int8" || t == "short" || t == "int16" || t == "int" || t == "int32";
  if (t == "char" || t == "int8" || t == "uchar" || t == "uint8") return 1;
  if (t == "short" || t == "int16" || t == "ushort" || t == "uint16") return 2;
  if (t == "int" || t == "int32" || t == "uint" || t == "uint32") return 4;
  if (t == "float" || t == "float32") return -4;
  if (t == "double" || t == "float64") return -8;
  return 0;
}

// One binary value of `type` (see ply_type) as a double.
bool ply_binary_value(std::istream& in, int type, bool is_signed, bool big_endian, double& out) {
  unsigned char b[8];
  const int size = type < 0 ? -type : type;
  if (!in.read(reinterpret_cast<char*>(b), size)) return false;
  if (big_endian) std::reverse(b, b + size);
  uint64_t u = 0;
  for (int k = size - 1; k >= 0; --k) u = u << 8 | b[k];
  if (type == -4) {
    float f;
    const uint32_t u32 = uint32_t(u);
    std::memcpy(&f, &u32, 4);
    out = f;
  } else if (type == -8) {
    std::memcpy(&out, &u, 8);
  } else if (is_signed) {
    const int shift = 64 - 8 * size;
    out = double(int64_t(u << shift) >> shift);  // sign-extend
  } else {
    out = double(u);
  }
  return true;
}

// The lines of a PLY file's text (the header; an ASCII body), counted for the messages.
struct PlyLines {
  std::istream& in;
  std::string line;
  int number = 0;
  bool next() {
    if (!std::getline(in, line)) return false;
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return true;
  }
};

// The header after its "ply" line: the format and the elements with their properties.
bool ply_header(PlyLines& lines, Reader r, std::string& format, std::vector<PlyElement>& elements) {
  while (true) {
    if (!lines.next()) return r.fail(lines.number, "header has no end_header");
    std::istringstream ss(lines.line);
    std::string key;
    ss >> key;
    if (key == "end_header") break;
    if (key == "format") {
      ss >> format;
      if (format != "ascii" && format != "binary_little_endian" && format != "binary_big_endian")
        return r.fail(lines.number, "unknown PLY format \"" + format + "\"");
    } else if (key == "element") {
      PlyElement e;
      std::string count;
      if (!(ss >> e.name >> count) || !parse_index(count, e.count) || e.count < 0 || e.count > kMaxCount)
        return r.fail(lines.number, "bad element line");
      elements.push_back(e);
    } else if (key == "property") {
      if (elements.empty()) return r.fail(lines.number, "a property before any element");
      PlyProperty p;
      std::string type;
      ss >> type;
      if (type == "list") {
        std::string count_type;
        bool count_signed = false;
        ss >> count_type >> type;
        p.count_type = ply_type(count_type, count_signed);
        if (p.count_type <= 0) return r.fail(lines.number, "a list count must be an integer type");
      }
      p.type = ply_type(type, p.is_signed);
      if (p.type == 0 || !(ss >> p.name)) return r.fail(lines.number, "bad property line");
      elements.back().properties.push_back(p);
    } else if (key != "comment" && key != "obj_info") {
      return r.fail(lines.number, "unknown header line \"" + key + "\"");
    }
  }
  if (format.empty()) return r.fail(lines.number, "the header has no format line");
  return true;
}

// Which properties are kept (the vertex element's x, y, z; the face element's index list),
// checked before the body is read.
bool ply_kept(std::vector<PlyElement>& elements, Reader r, int number) {
  int vertex_elements = 0;
  for (PlyElement& e : elements) {
    for (size_t p = 0; p < e.properties.size(); ++p) {
      const PlyProperty& q = e.properties[p];
      if (e.name == "vertex" && q.count_type == 0 && q.name.size() == 1 && q.name[0] >= 'x' && q.name[0] <= 'z')
        e.axis[q.name[0] - 'x'] = int(p);
      if (e.name == "face" && q.count_type != 0 && (q.name == "vertex_indices" || q.name == "vertex_index"))
        e.indices = int(p);
    }
    if (e.name == "vertex" && (++vertex_elements > 1 || e.axis[0] < 0 || e.axis[1] < 0 || e.axis[2] < 0))
      return r.fail(number, "the vertex element needs one x, y and z each");
    if (e.name == "face" && e.indices < 0) return r.fail(number, "the face element has no vertex_indices list");
  }
  if (vertex_elements == 0) return r.fail(number, "no vertex element");
  return true;
}

// Row k of element e: its x, y, z (if it has them) into xyz, its index list (if it has one)
// into polygon.
bool ply_row(PlyLines& lines, Reader r, const std::string& format, const PlyElement& e, long k, double (&xyz)[3],
             std::vector<long>& polygon) {
  const bool ascii = format == "ascii", big_endian = format == "binary_big_endian";
  std::istringstream ss;
  if (ascii) {
    if (!lines.next()) return r.fail(lines.number, "file ends before all " + e.name + " elements are read");
    ss.str(lines.line);
  }
  std::istream& src = ascii ? static_cast<std::istream&>(ss) : lines.in;
  const int at = ascii ? lines.number : 0;  // binary rows have no line
  // One value of `type`: from the line's next token, or from the binary stream.
  const auto value = [&](int type, bool is_signed, double& out) {
    if (!ascii) return ply_binary_value(src, type, is_signed, big_endian, out);
    std::string tok;
    char* end = nullptr;
    if (!(src >> tok)) return false;
    out = std::strtod(tok.c_str(), &end);
    if (type == -4 && std::isfinite(out)) out = double(float(out));  // as declared
    return end != tok.c_str() && *end == '\0';
  };
  for (size_t p = 0; p < e.properties.size(); ++p) {
    const PlyProperty& q = e.properties[p];
    double v = 0;
    long n = 1;
    if (q.count_type != 0) {
      if (!value(q.count_type, false, v) || !(v >= 0 && v <= 1e6) || v != std::floor(v))
        return r.fail(at, e.name + " " + std::to_string(k) + ": bad list count");
      n = long(v);
    }
    if (int(p) == e.indices) polygon.clear();
    for (long j = 0; j < n; ++j) {
      if (!value(q.type, q.is_signed, v))
        return r.fail(at, e.name + " " + std::to_string(k) + ": missing or malformed " + q.name);
      if (!std::isfinite(v)) return r.fail(at, e.name + " " + std::to_string(k) + ": " + q.name + " is not finite");
      if (int(p) == e.indices) {
        if (q.type < 0 || v != std::floor(v) || std::abs(v) > 1e15)
          return r.fail(at, "face " + std::to_string(k) + ": a vertex index must be an integer");
        polygon.push_back(long(v));
      }
      for (int a = 0; a < 3; ++a)
        if (q.count_type == 0 && int(p) == e.axis[a]) xyz[a] = v;
    }
  }
  std::string extra;
  if (ascii && ss >> extra) return r.fail(at, "more values than the " + e.name + " element's properties");
  return true;
}

bool read_ply(std::istream& in, Reader r, std::vector<Vector3d>& pts, Faces& faces) {
  PlyLines lines{in, {}, 0};
  if (!lines.next() || lines.line != "ply") return r.fail(1, "expected the ply header");
  std::string format;
  std::vector<PlyElement> elements;
  if (!ply_header(lines, r, format, elements) || !ply_kept(elements, r, lines.number)) return false;
  const bool ascii = format == "ascii";
  std::vector<long> polygon;
  for (const PlyElement& e : elements)
    for (long k = 0; k < e.count; ++k) {
      double xyz[3] = {0, 0, 0};
      if (!ply_row(lines, r, format, e, k, xyz, polygon)) return false;
      if (e.name == "vertex") pts.emplace_back(xyz[0], xyz[1], xyz[2]);
      if (e.indices >= 0) faces.add(polygon, ascii ? lines.number : 0);
    }
  if (ascii ? lines.next() && lines.line.find_first_not_of(" \t") != std::string::npos : in.peek() != EOF)
    return r.fail(ascii ? lines.number : 0, "more data after the last element");
  return true;
}

// A directory opens as a stream, then reads as empty: say what it is.
bool readable_file(const std::string& path, std::string& error) {
  std::error_code code;
  if (std::filesystem::is_directory(path, code)) return error = path + ": is a directory, not a file", false;
  return true;
}

// STL, binary (80 bytes of header, a count n, then n records of 50 bytes: a normal and three
// corners as little-endian floats, two attribute bytes) when the file is exactly 84 + 50 n
// bytes, else ASCII ("solid", then "facet normal ..., outer loop, vertex x y z (three times),
// endloop, endfacet", "endsolid"). Three vertices per triangle, as written (no welding).
bool read_stl(std::istream& in, Reader r, std::vector<Vector3d>& pts, std::vector<std::array<int, 3>>& triangles) {
  char head[84] = {};
  in.read(head, 84);
  const auto got = in.gcount();
  in.clear();
  in.seekg(0, std::ios::end);
  const long long bytes = static_cast<long long>(in.tellg());
  uint32_t n = 0;
  std::memcpy(&n, head + 80, 4);  // (x86-64 and every target of the library: little-endian)
  if (got == 84 && bytes == 84 + 50LL * n) {
    in.seekg(84);
    for (uint32_t t = 0; t < n; ++t) {
      char record[50];
      if (!in.read(record, 50)) return r.fail(0, "triangle " + std::to_string(t) + ": the file ends");
      for (int v = 0; v < 3; ++v) {
        float xyz[3];
        std::memcpy(xyz, record + 12 + 12 * v, 12);
        if (!std::isfinite(xyz[0]) || !std::isfinite(xyz[1]) || !std::isfinite(xyz[2]))
          return r.fail(0, "triangle " + std::to_string(t) + ": a coordinate is NaN or Inf");
        pts.emplace_back(xyz[0], xyz[1], xyz[2]);
      }
      const int base = int(pts.size()) - 3;
      triangles.push_back({base, base + 1, base + 2});
    }
    return true;
  }
  in.seekg(0);
  Lines lines{in};
  std::string line, word;
  const auto expect = [&](const char* what) {
    if (!lines.next(line)) return r.fail(lines.number, std::string("the file ends where \"") + what + "\" belongs");
    std::istringstream ss(line);
    ss >> word;
    return word == what || r.fail(lines.number, std::string("expected \"") + what + "\", found \"" + word + "\"");
  };
  if (!expect("solid")) return r.fail(lines.number, "not an STL file (neither \"solid\" nor 84 + 50 n bytes)");
  while (lines.next(line)) {
    std::istringstream ss(line);
    ss >> word;
    if (word == "endsolid") break;
    if (word != "facet") return r.fail(lines.number, "expected \"facet\" or \"endsolid\", found \"" + word + "\"");
    if (!expect("outer")) return false;
    for (int v = 0; v < 3; ++v) {
      if (!expect("vertex")) return false;
      double xyz[3];
      if (!parse_numbers(line.substr(line.find("vertex") + 6), 3, xyz, false))
        return r.fail(lines.number, "a vertex needs three finite coordinates");
      pts.emplace_back(xyz[0], xyz[1], xyz[2]);
    }
    if (!expect("endloop") || !expect("endfacet")) return false;
    const int base = int(pts.size()) - 3;
    triangles.push_back({base, base + 1, base + 2});
  }
  if (word != "endsolid") return r.fail(lines.number, "the file ends without \"endsolid\"");
  if (lines.next(line)) return r.fail(lines.number, "more data after \"endsolid\"");
  return true;
}

}  // namespace

bool read_polygons(std::istream& in, const std::string& name, std::string format, std::vector<Vector3d>& points,
                   std::vector<std::array<int, 3>>* triangles, std::string& error) {
  points.clear();
  if (triangles) triangles->clear();
  Reader r{name, error};
  if (!in) return r.fail(0, "cannot open file");
  if (format != "off" && format != "obj" && format != "ply") {  // sniff the content instead
    std::string first;
    in >> first;
    in.clear();
    in.seekg(0);
    format = first == "OFF" ? "off" : first == "ply" ? "ply" : "txt";
  }
  Faces faces;
  const bool ok = format == "off"   ? read_off(in, r, points, faces)
                  : format == "obj" ? read_obj(in, r, points, faces)
                  : format == "ply" ? read_ply(in, r, points, faces)
                                    : read_plain(in, r, points, faces);
  if (!ok || !faces.finish(r, points.size(), triangles)) return false;
  if (points.empty()) return r.fail(0, "no vertices");
  return true;
}

bool read_points(const std::string& path, std::vector<Vector3d>& points, std::string& error) {
  if (!readable_file(path, error)) return false;
  std::ifstream in(path, std::ios::binary);
  return read_polygons(in, path, lower_extension(path), points, nullptr, error);
}

bool read_mesh(const std::string& path, std::vector<Vector3d>& vertices, std::vector<std::array<int, 3>>& triangles,
               std::string& error, bool cloud_ok) {
  vertices.clear(), triangles.clear();
  if (!readable_file(path, error)) return false;
  std::ifstream in(path, std::ios::binary);
  if (!in) return error = path + ": cannot open file", false;
  const std::string ext = lower_extension(path);
  if (ext == "stl") {
    Reader r{path, error};
    if (!read_stl(in, r, vertices, triangles)) return false;
  } else if (!read_polygons(in, path, ext, vertices, &triangles, error)) {
    return false;
  }
  if (triangles.empty() && !(cloud_ok && !vertices.empty()))
    return error = path + (cloud_ok ? ": no points in the file" : ": no triangles in the file"), false;
  return true;
}

bool write_mesh(const std::string& path, const MinkowskiSum& sum, std::string& error, bool core) {
  if (sum.vertices.empty() && sum.planes.empty())
    return error = path + ": the sum is empty (a failed call's result): nothing to write", false;
  if (sum.parts != SumParts::Whole || int(sum.loop_start.size()) != sum.F + 1 || int(sum.vertices.size()) != sum.V)
    return error = path + ": the sum has no facet loops (computed with SumParts::Planes or Vertices): compute it whole",
           false;
  if (sum.radius > 0 && !core) {
    std::ostringstream r;
    r.precision(17);
    r << sum.radius;
    error = path + ": a rounded sum (radius " + r.str() + ") is not a polygon mesh; ask for its core (core=True)";
    return false;
  }
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
  const size_t V = sum.vertices.size(), F = size_t(sum.F);
  if (ext == "off") out << "OFF\n" << V << ' ' << F << " 0\n";
  if (ext == "ply")
    out << "ply\nformat ascii 1.0\nelement vertex " << V
        << "\nproperty double x\nproperty double y\nproperty double z\nelement face " << F
        << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const auto& v : sum.vertices)
    out << (ext == "obj" ? "v " : "") << v.point.x() << ' ' << v.point.y() << ' ' << v.point.z() << '\n';
  for (int k = 0; k < sum.F; ++k) {
    const Loop f = sum.facet(k);
    out << (ext == "obj" ? "f" : std::to_string(f.size()));
    for (int k : f) out << ' ' << (ext == "obj" ? k + 1 : k);
    out << '\n';
  }
  if (!out) {
    out.close();
    std::remove(path.c_str());  // (not half a mesh)
    error = path + ": write failed";
    return false;
  }
  return true;
}

}  // namespace minksum
