// fracture_check: an independent checker of what `dawnforge fracture MESH -o DIR` writes.
//
//   fracture_check FRACTURE_DIR REFERENCE_MESH [--samples N] [--seed S]
//
// Reads DIR/fragments.glb, DIR/fracture.json and a reference mesh (the input: GLB/glTF with node
// transforms applied, e.g. from `dawnforge inspect IN --repair REF.glb`, or OBJ/OFF), and shares
// no code with dawnforge: only the standard library, tinygltf and nlohmann-json. Everything is
// computed in double from the float values stored in the files. Prints one JSON object (counts,
// largest deviations, "failures": short examples per check, "warnings") and exits 0 when every
// check passes, 1 when one fails, 2 when a file cannot be read (or the reference is not closed).
// Made for exact (planar) cuts: `--roughness` output fails the volume, coverage and bond checks
// by design of that mode (voxel meshing moves volume by ~1%).
//
// Build: g++ -std=c++20 -O2 -o fracture_check tests/corpus/fracture_check.cpp
// (tinygltf's implementation is compiled into this file; nothing to link.)
// Self-test: tests/corpus/check_selftest.sh [CHECKER] [DAWNFORGE].
//
// What it checks, and why each tolerance is what it is. diag = the diagonal of the bounding box
// of the pieces and the reference together; "seen" = on clean outputs of cube, sphere, joint,
// elephant and armadillo, 20 to 1000 pieces.
//
// * Each piece, after welding vertices by exact float position: no degenerate triangle (a
//   repeated index, two corners at one position, an exactly zero cross product); every edge
//   used by exactly two triangles, once in each direction; the triangles around each vertex
//   form one fan (no pinched vertex); positive signed volume. Exact tests: a welded float mesh
//   either is closed and clean or is not, and any such defect breaks normals, physics hulls
//   and inside tests downstream.
// * Against fracture.json: piece count, names, triangle counts, `closed` (as `inspect` defines
//   it: no boundary edge, no edge used by 3+ triangles), _PIECE_ID on every vertex.
//   - volume within 1e-6 relative + what rounding can change (surface area * half an ulp of
//     the coordinates): dawnforge's volumes differ from the float meshes' by 3e-8..3e-7
//     relative (seen; they seem to be computed before rounding), so 1e-6 still catches a
//     wrong piece. mass = density * volume within 1e-9 (same numbers, one product).
//   - node translation and our own centroid within 1e-6 * diag (+2 ulp of the coordinates) of
//     `center_of_mass`: seen 1.7e-8 * diag.
//   - our own inertia tensor (about the centroid, world axes) within 1e-6 of its largest entry
//     (+ the rounding term relative to the volume): seen 3e-7.
// * Volumes add up: the pieces' volumes sum to the reference's within 1e-6 relative. Rounding
//   cut vertices to float moves the two sides of a cut independently; seen: at most 1.1e-8.
// * No overlap, full coverage: N points (default 20000; mt19937_64 seeded by --seed, our own
//   conversion to [0,1)) uniform in the bounding box of the pieces and the reference (a superset
//   of the union of the piece boxes, so that a hole outside every piece's box shows too). Each
//   point is classified against every piece whose box holds it, and the reference, by ray
//   parity: a fixed generic direction, a 2D grid over the triangles projected along it, and
//   each shared edge's side test evaluated in one canonical vertex order so that neighbouring
//   triangles never both miss or both count a ray; a ray exactly through an edge or vertex is
//   retried along another direction. Points within 1e-6 * diag of a face of any candidate are
//   skipped: rounding moves shared faces by ~1e-8 * diag, so farther points are classified the
//   same for any reading of the surface. Fails on any point inside two pieces (beyond that
//   distance it is a real overlap) and when the points inside the reference but in no piece, or
//   in a piece but outside the reference, exceed 1e-3 of the points inside the reference. Seen:
//   exactly 0 of each, so 1e-3 is not there to absorb noise: it keeps a few stray points from
//   an open piece (whose parity is meaningless) from doubling the failure while a missing piece
//   (1/200 of the volume is 5e-3) still fails; a missing sliver is the volume check's job.
// * Bonds: both pieces exist, a < b, no duplicate, area > 0, |normal| = 1 within 1e-6, and the
//   centroid within 1e-5 * diag of both pieces' surfaces, unless it is the centroid of the shared
//   face as measured below (a non-convex shared face has its centroid off itself).
//   Contacts are measured from the meshes: triangles of two pieces with opposite normals (cosine
//   < -0.999) whose overlap, clipped in one's plane, lies within 1e-6 * diag (+4 ulp of the
//   coordinates) of the other's plane; summed per pair: area, centroid, mean normal. Seen on
//   clean bonds: area within 2.5e-5 relative on faces above 1e-6 * diag^2 and up to 4e-3 on
//   faces of 1e-10 m^2 (one ulp of an edge is a large part of them), centroid within 1e-7 * diag,
//   normal within 1.2e-3 rad (tiny faces). So only clear cases fail: a bond whose pieces share
//   no face; area off by more than 1e-2 relative and 1e-6 * diag^2; centroid off by more than
//   1e-3 * diag; a normal more than 120 degrees from the measured one (a flip; a contact over
//   several planes, after --min-volume merges, may legitimately be far from any one face); a
//   touching pair without a bond sharing more than 1e-6 * diag^2 (smaller ones, which rounding
//   can create, are warnings). Area beyond 1e-3 relative and 1e-9 * diag^2, centroid beyond
//   1e-5 * diag and normal beyond 1e-2 rad are warnings.

#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <numeric>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <unordered_map>
#include <vector>

namespace {

using Json = nlohmann::ordered_json;

// ---------------------------------------------------------------------------------------------
// Small vector math (double).

struct Vec3 {
  double x = 0, y = 0, z = 0;
  double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  double& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
};
Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Vec3 operator*(Vec3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Vec3 cross(Vec3 a, Vec3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double norm(Vec3 a) { return std::sqrt(dot(a, a)); }
Vec3 normalized(Vec3 a) { return a * (1.0 / norm(a)); }
double maxAbs(Vec3 a) { return std::max({std::fabs(a.x), std::fabs(a.y), std::fabs(a.z)}); }

std::string fmt(Vec3 p) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.6g %.6g %.6g)", p.x, p.y, p.z);
  return buf;
}
std::string fmt(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

struct Box {
  Vec3 lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  void add(Vec3 p) {
    for (int i = 0; i < 3; ++i) lo[i] = std::min(lo[i], p[i]), hi[i] = std::max(hi[i], p[i]);
  }
  void add(const Box& b) { add(b.lo), add(b.hi); }
  bool empty() const { return lo.x > hi.x; }
  Box inflated(double e) const { return {lo - Vec3{e, e, e}, hi + Vec3{e, e, e}}; }
  bool contains(Vec3 p) const {
    return p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y && p.z >= lo.z && p.z <= hi.z;
  }
  bool overlaps(const Box& b) const {
    return lo.x <= b.hi.x && b.lo.x <= hi.x && lo.y <= b.hi.y && b.lo.y <= hi.y && lo.z <= b.hi.z &&
           b.lo.z <= hi.z;
  }
  double diagonal() const { return empty() ? 0.0 : norm(hi - lo); }
};

// ---------------------------------------------------------------------------------------------
// Report: counts and failure examples.

class Report {
 public:
  Json counts = Json::object();
  Json warnings = Json::object();

  // Records a failure of `check`; keeps the first few examples of each check.
  void fail(const std::string& check, const std::string& example) {
    auto& c = failures_[check];
    if (c.first++ < kExamples) c.second.push_back(example);
  }
  void warn(const std::string& what, const std::string& example) {
    auto& w = warnings[what];
    if (w.is_null()) w = Json{{"count", 0}, {"examples", Json::array()}};
    w["count"] = w["count"].get<int>() + 1;
    if (w["examples"].size() < kExamples) w["examples"].push_back(example);
  }
  bool failed() const { return !failures_.empty(); }
  Json failureList() const {
    Json list = Json::array();
    for (const auto& [check, c] : failures_) {
      for (const auto& e : c.second) list.push_back(check + ": " + e);
      if (c.first > c.second.size())
        list.push_back(check + ": " + std::to_string(c.first - c.second.size()) + " more");
    }
    return list;
  }
  Json failureCounts() const {
    Json j = Json::object();
    for (const auto& [check, c] : failures_) j[check] = c.first;
    return j;
  }

 private:
  static constexpr size_t kExamples = 5;
  std::map<std::string, std::pair<size_t, std::vector<std::string>>> failures_;
};

// ---------------------------------------------------------------------------------------------
// Meshes. Vertices are welded by exact position; a piece's vertices stay in its own frame
// (relative to its pivot, as stored) so that its topology and volume use the float values as
// they are, and `offset` takes them to world space.

using Tri = std::array<uint32_t, 3>;

struct Mesh {
  std::string name;
  Vec3 offset;                // world position of the mesh's frame origin (a piece's translation)
  std::vector<Vec3> v;        // welded vertices, mesh frame
  std::vector<Tri> t;         // triangles on welded vertices
  size_t repeatedIndex = 0;   // triangles with a repeated index as stored (before welding)
  Box localBox, worldBox;
};

struct Vec3Hash {
  size_t operator()(const Vec3& p) const {
    auto h = [](double d) { return std::hash<double>()(d + 0.0); };  // +0.0: -0 welds with 0
    return h(p.x) * 73856093u ^ h(p.y) * 19349663u ^ h(p.z) * 83492791u;
  }
};
struct Vec3Eq {
  bool operator()(const Vec3& a, const Vec3& b) const { return a.x == b.x && a.y == b.y && a.z == b.z; }
};

// Adds triangles over `positions` (one position per stored index) to `mesh`, welding by position.
void addTriangles(Mesh& mesh, const std::vector<Vec3>& positions, const std::vector<uint32_t>& indices,
                  std::unordered_map<Vec3, uint32_t, Vec3Hash, Vec3Eq>& weld) {
  std::vector<uint32_t> welded(positions.size());
  for (size_t i = 0; i < positions.size(); ++i) {
    auto [it, fresh] = weld.try_emplace(positions[i], uint32_t(mesh.v.size()));
    if (fresh) mesh.v.push_back(positions[i]);
    welded[i] = it->second;
  }
  for (size_t i = 0; i + 2 < indices.size(); i += 3) {
    const uint32_t a = indices[i], b = indices[i + 1], c = indices[i + 2];
    if (a == b || b == c || a == c) ++mesh.repeatedIndex;
    mesh.t.push_back({welded[a], welded[b], welded[c]});
  }
}

void finishBoxes(Mesh& m) {
  for (const Tri& t : m.t)
    for (uint32_t i : t) m.localBox.add(m.v[i]);
  m.worldBox = m.localBox.empty() ? Box{} : Box{m.localBox.lo + m.offset, m.localBox.hi + m.offset};
}

// ---------------------------------------------------------------------------------------------
// glTF reading.

struct ReadError {
  std::string what;
};

// Reads accessor `index` as doubles, `comps` per element; normalized integers are scaled.
std::vector<double> readAccessor(const tinygltf::Model& m, int index, int& comps) {
  if (index < 0 || index >= int(m.accessors.size())) throw ReadError{"accessor index out of range"};
  const auto& acc = m.accessors[index];
  if (acc.sparse.isSparse) throw ReadError{"sparse accessors are not supported"};
  comps = tinygltf::GetNumComponentsInType(acc.type);
  const int size = tinygltf::GetComponentSizeInBytes(acc.componentType);
  if (comps <= 0 || size <= 0 || acc.bufferView < 0) throw ReadError{"unsupported accessor"};
  const auto& view = m.bufferViews.at(acc.bufferView);
  const auto& buf = m.buffers.at(view.buffer).data;
  const size_t stride = view.byteStride ? view.byteStride : size_t(comps * size);
  const size_t start = view.byteOffset + acc.byteOffset;
  if (acc.count > 0 && start + stride * (acc.count - 1) + comps * size > buf.size())
    throw ReadError{"accessor runs past its buffer"};
  std::vector<double> out(acc.count * comps);
  for (size_t i = 0; i < acc.count; ++i) {
    const unsigned char* p = buf.data() + start + i * stride;
    for (int c = 0; c < comps; ++c, p += size) {
      double v = 0;
      switch (acc.componentType) {
        case TINYGLTF_COMPONENT_TYPE_FLOAT: { float f; std::memcpy(&f, p, 4); v = f; break; }
        case TINYGLTF_COMPONENT_TYPE_DOUBLE: { double d; std::memcpy(&d, p, 8); v = d; break; }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: v = *p; if (acc.normalized) v /= 255.0; break;
        case TINYGLTF_COMPONENT_TYPE_BYTE: v = int8_t(*p); if (acc.normalized) v = std::max(v / 127.0, -1.0); break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { uint16_t s; std::memcpy(&s, p, 2); v = s; if (acc.normalized) v /= 65535.0; break; }
        case TINYGLTF_COMPONENT_TYPE_SHORT: { int16_t s; std::memcpy(&s, p, 2); v = s; if (acc.normalized) v = std::max(v / 32767.0, -1.0); break; }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: { uint32_t u; std::memcpy(&u, p, 4); v = u; break; }
        case TINYGLTF_COMPONENT_TYPE_INT: { int32_t s; std::memcpy(&s, p, 4); v = s; break; }
        default: throw ReadError{"unknown component type"};
      }
      out[i * comps + c] = v;
    }
  }
  return out;
}

// Geometry only: pictures (fragments.glb embeds its materials') are neither decoded nor needed.
bool skipImage(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int, void*) {
  return true;
}

tinygltf::Model loadGltf(const std::string& path) {
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(skipImage, nullptr);
  tinygltf::Model model;
  std::string err, warn;
  const bool binary = path.size() >= 4 && path.compare(path.size() - 4, 4, ".glb") == 0;
  const bool ok = binary ? loader.LoadBinaryFromFile(&model, &err, &warn, path)
                         : loader.LoadASCIIFromFile(&model, &err, &warn, path);
  if (!ok) throw ReadError{path + ": " + (err.empty() ? "cannot read" : err)};
  return model;
}

// Positions and indices of one triangle primitive, positions as stored (float -> double).
void readPrimitive(const tinygltf::Model& m, const tinygltf::Primitive& prim, std::vector<Vec3>& pos,
                   std::vector<uint32_t>& idx) {
  const auto it = prim.attributes.find("POSITION");
  if (it == prim.attributes.end()) throw ReadError{"primitive without POSITION"};
  int comps = 0;
  const auto p = readAccessor(m, it->second, comps);
  if (comps != 3) throw ReadError{"POSITION is not VEC3"};
  pos.resize(p.size() / 3);
  for (size_t i = 0; i < pos.size(); ++i) pos[i] = {p[3 * i], p[3 * i + 1], p[3 * i + 2]};
  idx.clear();
  if (prim.indices >= 0) {
    const auto raw = readAccessor(m, prim.indices, comps);
    for (double d : raw) {
      if (d < 0 || d >= double(pos.size())) throw ReadError{"index out of range"};
      idx.push_back(uint32_t(d));
    }
  } else {
    idx.resize(pos.size());
    std::iota(idx.begin(), idx.end(), 0u);
  }
  if (idx.size() % 3 != 0) throw ReadError{"index count is not a multiple of 3"};
}

// 4x4 column-major affine transforms, as glTF stores them.
using Mat4 = std::array<double, 16>;
Mat4 identity() { return {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}; }
Mat4 mul(const Mat4& a, const Mat4& b) {
  Mat4 r{};
  for (int c = 0; c < 4; ++c)
    for (int rr = 0; rr < 4; ++rr)
      for (int k = 0; k < 4; ++k) r[c * 4 + rr] += a[k * 4 + rr] * b[c * 4 + k];
  return r;
}
Vec3 apply(const Mat4& m, Vec3 p) {
  return {m[0] * p.x + m[4] * p.y + m[8] * p.z + m[12], m[1] * p.x + m[5] * p.y + m[9] * p.z + m[13],
          m[2] * p.x + m[6] * p.y + m[10] * p.z + m[14]};
}
Mat4 nodeMatrix(const tinygltf::Node& n) {
  if (n.matrix.size() == 16) {
    Mat4 m;
    std::copy(n.matrix.begin(), n.matrix.end(), m.begin());
    return m;
  }
  Mat4 t = identity(), r = identity(), s = identity();
  if (n.translation.size() == 3) t[12] = n.translation[0], t[13] = n.translation[1], t[14] = n.translation[2];
  if (n.scale.size() == 3) s[0] = n.scale[0], s[5] = n.scale[1], s[10] = n.scale[2];
  if (n.rotation.size() == 4) {
    const double x = n.rotation[0], y = n.rotation[1], z = n.rotation[2], w = n.rotation[3];
    r = {1 - 2 * (y * y + z * z), 2 * (x * y + z * w),     2 * (x * z - y * w),     0,
         2 * (x * y - z * w),     1 - 2 * (x * x + z * z), 2 * (y * z + x * w),     0,
         2 * (x * z + y * w),     2 * (y * z - x * w),     1 - 2 * (x * x + y * y), 0,
         0, 0, 0, 1};
  }
  return mul(t, mul(r, s));
}

// The reference mesh from a glTF file: every triangle primitive of every node of the scene, in
// world space, welded by world position.
void addGltfNode(const tinygltf::Model& m, int node, const Mat4& parent, Mesh& out,
                 std::unordered_map<Vec3, uint32_t, Vec3Hash, Vec3Eq>& weld, int depth) {
  if (depth > 64) throw ReadError{"node hierarchy too deep (cycle?)"};
  const auto& n = m.nodes.at(node);
  const Mat4 world = mul(parent, nodeMatrix(n));
  if (n.mesh >= 0) {
    for (const auto& prim : m.meshes.at(n.mesh).primitives) {
      if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != -1) continue;
      std::vector<Vec3> pos;
      std::vector<uint32_t> idx;
      readPrimitive(m, prim, pos, idx);
      for (Vec3& p : pos) p = apply(world, p);
      addTriangles(out, pos, idx, weld);
    }
  }
  for (int c : n.children) addGltfNode(m, c, world, out, weld, depth + 1);
}

Mesh loadReferenceGltf(const std::string& path) {
  const auto model = loadGltf(path);
  Mesh mesh;
  mesh.name = "reference";
  std::unordered_map<Vec3, uint32_t, Vec3Hash, Vec3Eq> weld;
  const int scene = model.defaultScene >= 0 ? model.defaultScene : 0;
  if (model.scenes.empty()) {
    for (size_t i = 0; i < model.nodes.size(); ++i) addGltfNode(model, int(i), identity(), mesh, weld, 0);
  } else {
    for (int n : model.scenes.at(scene).nodes) addGltfNode(model, n, identity(), mesh, weld, 0);
  }
  return mesh;
}

// OBJ (v and f lines; polygons as fans) and OFF, for convenience when no GLB is at hand.
Mesh loadReferenceText(const std::string& path, bool off) {
  std::ifstream in(path);
  if (!in) throw ReadError{path + ": cannot open"};
  std::vector<Vec3> pos;
  std::vector<uint32_t> idx;
  auto addFace = [&](const std::vector<long>& f) {
    for (size_t k = 1; k + 1 < f.size(); ++k) {
      for (long i : {f[0], f[k], f[k + 1]}) {
        if (i < 0 || i >= long(pos.size())) throw ReadError{path + ": face index out of range"};
        idx.push_back(uint32_t(i));
      }
    }
  };
  std::string line;
  if (off) {
    std::vector<std::string> tok;  // OFF is whitespace-separated tokens; '#' starts a comment
    while (std::getline(in, line)) {
      std::istringstream ls(line.substr(0, line.find('#')));
      for (std::string t; ls >> t;) tok.push_back(t);
    }
    size_t i = 0;
    if (tok.empty() || tok[i++].find("OFF") == std::string::npos) throw ReadError{path + ": not OFF"};
    if (tok.size() < 4) throw ReadError{path + ": truncated"};
    const size_t nv = std::stoul(tok[i]), nf = std::stoul(tok[i + 1]);
    i += 3;
    for (size_t k = 0; k < nv; ++k, i += 3) {
      if (i + 3 > tok.size()) throw ReadError{path + ": truncated"};
      pos.push_back({std::stod(tok[i]), std::stod(tok[i + 1]), std::stod(tok[i + 2])});
    }
    for (size_t k = 0; k < nf; ++k) {
      if (i >= tok.size()) throw ReadError{path + ": truncated"};
      const size_t n = std::stoul(tok[i++]);
      if (i + n > tok.size()) throw ReadError{path + ": truncated"};
      std::vector<long> f;
      for (size_t j = 0; j < n; ++j) f.push_back(std::stol(tok[i++]));
      addFace(f);
      // Optional per-face colour values would follow on the same line; not supported.
    }
  } else {
    while (std::getline(in, line)) {
      std::istringstream ls(line);
      std::string kind;
      ls >> kind;
      if (kind == "v") {
        Vec3 p;
        ls >> p.x >> p.y >> p.z;
        pos.push_back(p);
      } else if (kind == "f") {
        std::vector<long> f;
        for (std::string t; ls >> t;) {
          const long i = std::stol(t.substr(0, t.find('/')));
          f.push_back(i < 0 ? long(pos.size()) + i : i - 1);
        }
        addFace(f);
      }
    }
  }
  // Like a glTF reader would, store the positions as floats.
  for (Vec3& p : pos) p = {double(float(p.x)), double(float(p.y)), double(float(p.z))};
  Mesh mesh;
  mesh.name = "reference";
  std::unordered_map<Vec3, uint32_t, Vec3Hash, Vec3Eq> weld;
  addTriangles(mesh, pos, idx, weld);
  return mesh;
}

Mesh loadReference(const std::string& path) {
  auto ends = [&](const char* s) {
    const size_t n = std::strlen(s);
    if (path.size() < n) return false;
    std::string tail = path.substr(path.size() - n);
    std::transform(tail.begin(), tail.end(), tail.begin(), ::tolower);
    return tail == s;
  };
  Mesh m = ends(".obj") ? loadReferenceText(path, false)
         : ends(".off") ? loadReferenceText(path, true)
                        : loadReferenceGltf(path);
  if (m.t.empty()) throw ReadError{path + ": no triangles"};
  finishBoxes(m);
  return m;
}

std::string pieceName(size_t i) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "piece_%04zu", i);
  return buf;
}

// The pieces: the scene's root nodes, each with one indexed triangle primitive. Format
// deviations are failures, not read errors, so that the rest still gets checked.
std::vector<Mesh> loadPieces(const std::string& path, Report& report) {
  const auto model = loadGltf(path);
  if (model.scenes.empty()) throw ReadError{path + ": no scene"};
  const auto& scene = model.scenes.at(model.defaultScene >= 0 ? model.defaultScene : 0);
  std::vector<Mesh> pieces;
  for (int nodeIndex : scene.nodes) {
    const auto& node = model.nodes.at(nodeIndex);
    Mesh mesh;
    mesh.name = node.name;
    const size_t id = pieces.size();
    if (node.name != pieceName(id)) report.fail("format", "root node " + std::to_string(id) + " is named '" + node.name + "', expected " + pieceName(id));
    if (!node.rotation.empty() || !node.scale.empty() || !node.matrix.empty() || !node.children.empty())
      report.fail("format", node.name + ": node has rotation, scale, matrix or children");
    if (node.translation.size() == 3) mesh.offset = {node.translation[0], node.translation[1], node.translation[2]};
    else report.fail("format", node.name + ": node has no translation (pivot)");
    if (node.mesh < 0 || model.meshes.at(node.mesh).primitives.empty()) {
      report.fail("format", node.name + ": node needs a mesh with primitives");
      finishBoxes(mesh); pieces.push_back(std::move(mesh)); continue;
    }
    // One primitive per material, all of them on the same vertices.
    const auto& prims = model.meshes.at(node.mesh).primitives;
    const auto& prim = prims.at(0);
    for (const auto& other : prims)
      if (other.attributes != prim.attributes) report.fail("format", node.name + ": primitives on different vertices");
    if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != -1) report.fail("format", node.name + ": primitive mode is not TRIANGLES");
    if (prim.indices < 0) report.fail("format", node.name + ": primitive is not indexed");
    for (const char* a : {"POSITION", "NORMAL", "TEXCOORD_0", "_MATERIAL_ID", "_PIECE_ID"})
      if (!prim.attributes.count(a)) report.fail("format", node.name + ": missing attribute " + a);
    if (prim.attributes.count("POSITION")) {
      const auto& acc = model.accessors.at(prim.attributes.at("POSITION"));
      if (acc.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT || acc.type != TINYGLTF_TYPE_VEC3)
        report.fail("format", node.name + ": POSITION is not float VEC3");
    }
    if (prim.attributes.count("_PIECE_ID")) {
      int comps = 0;
      for (double v : readAccessor(model, prim.attributes.at("_PIECE_ID"), comps))
        if (v != double(id)) { report.fail("format", node.name + ": _PIECE_ID " + fmt(v) + " on a vertex"); break; }
    }
    std::vector<Vec3> pos;
    std::vector<uint32_t> idx;
    std::unordered_map<Vec3, uint32_t, Vec3Hash, Vec3Eq> weld;
    for (const auto& part : prims) {
      readPrimitive(model, part, pos, idx);
      addTriangles(mesh, pos, idx, weld);
    }
    finishBoxes(mesh);
    pieces.push_back(std::move(mesh));
  }
  return pieces;
}

// ---------------------------------------------------------------------------------------------
// Topology: degenerate triangles, edges, fans, orientation.

struct Topology {
  size_t repeatedIndex = 0, samePosition = 0, zeroArea = 0;
  size_t boundaryEdges = 0, nonManifoldEdges = 0, misorientedEdges = 0, pinchedVertices = 0;
  // Closed as `dawnforge inspect` documents it: no boundary edge, no edge used by 3+ triangles.
  bool closed() const { return boundaryEdges == 0 && nonManifoldEdges == 0; }
  bool closedManifold() const {
    return boundaryEdges == 0 && nonManifoldEdges == 0 && misorientedEdges == 0 && pinchedVertices == 0;
  }
};

struct UnionFind {
  std::vector<uint32_t> parent;
  explicit UnionFind(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  uint32_t find(uint32_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  }
  void unite(uint32_t a, uint32_t b) { parent[find(a)] = find(b); }
};

bool hasRepeatedCorner(const Tri& t) { return t[0] == t[1] || t[1] == t[2] || t[0] == t[2]; }

Topology checkTopology(const Mesh& m, Report& report) {
  Topology topo;
  topo.repeatedIndex = m.repeatedIndex;
  if (m.repeatedIndex) report.fail("degenerate", m.name + ": " + std::to_string(m.repeatedIndex) + " triangles repeat an index");
  auto where = [&](uint32_t v) { return fmt(m.v[v] + m.offset); };
  auto edgeAt = [&](uint32_t a, uint32_t b) { return fmt((m.v[a] + m.v[b]) * 0.5 + m.offset); };  // its midpoint

  // Degenerate triangles. Corners welded together = same float position.
  for (const Tri& t : m.t) {
    if (hasRepeatedCorner(t)) {
      ++topo.samePosition;
      report.fail("degenerate", m.name + ": two corners at one position " + where(t[1] == t[2] ? t[1] : t[0]));
    } else if (Vec3 c = cross(m.v[t[1]] - m.v[t[0]], m.v[t[2]] - m.v[t[0]]); c.x == 0 && c.y == 0 && c.z == 0) {
      ++topo.zeroArea;
      report.fail("degenerate", m.name + ": zero-area triangle at " + where(t[0]));
    }
  }

  // Edges: one record per triangle side, sorted so that the uses of an edge are adjacent.
  struct Use { uint64_t key; uint32_t tri; bool forward; };
  std::vector<Use> uses;
  uses.reserve(m.t.size() * 3);
  for (uint32_t i = 0; i < m.t.size(); ++i) {
    const Tri& t = m.t[i];
    if (hasRepeatedCorner(t)) continue;  // already reported; it has no proper edges
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = t[k], b = t[(k + 1) % 3];
      uses.push_back({uint64_t(std::min(a, b)) << 32 | std::max(a, b), i, a < b});
    }
  }
  std::sort(uses.begin(), uses.end(), [](const Use& x, const Use& y) { return x.key < y.key; });

  // Corners of triangles sharing an edge are joined; a vertex whose corners end up in several
  // groups has several fans (pinched). Non-manifold edges join all their triangles, so that only
  // vertex-only contacts count as pinches.
  UnionFind corners(m.t.size() * 3);
  auto corner = [&](uint32_t tri, uint32_t v) {
    const Tri& t = m.t[tri];
    return tri * 3 + (t[0] == v ? 0 : (t[1] == v ? 1 : 2));
  };
  for (size_t i = 0; i < uses.size();) {
    size_t j = i;
    int forward = 0;
    while (j < uses.size() && uses[j].key == uses[i].key) forward += uses[j++].forward;
    const size_t n = j - i;
    const uint32_t a = uint32_t(uses[i].key >> 32), b = uint32_t(uses[i].key);
    if (n == 1) {
      ++topo.boundaryEdges;
      report.fail("not_closed", m.name + ": boundary edge at " + edgeAt(a, b));
    } else if (n > 2) {
      ++topo.nonManifoldEdges;
      report.fail("non_manifold", m.name + ": edge used by " + std::to_string(n) + " triangles at " + edgeAt(a, b));
    } else if (forward != 1) {
      ++topo.misorientedEdges;
      report.fail("orientation", m.name + ": edge walked twice in one direction at " + edgeAt(a, b));
    }
    for (size_t k = i + 1; k < j; ++k) {
      corners.unite(corner(uses[i].tri, a), corner(uses[k].tri, a));
      corners.unite(corner(uses[i].tri, b), corner(uses[k].tri, b));
    }
    i = j;
  }
  std::vector<uint32_t> fanRoot(m.v.size(), UINT32_MAX);
  std::vector<bool> pinched(m.v.size(), false);
  for (uint32_t i = 0; i < m.t.size(); ++i) {
    if (hasRepeatedCorner(m.t[i])) continue;
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = m.t[i][k], root = corners.find(i * 3 + k);
      if (fanRoot[v] == UINT32_MAX) fanRoot[v] = root;
      else if (fanRoot[v] != root && !pinched[v]) {
        pinched[v] = true;
        ++topo.pinchedVertices;
        report.fail("non_manifold", m.name + ": pinched vertex (several fans) at " + where(v));
      }
    }
  }
  return topo;
}

// ---------------------------------------------------------------------------------------------
// Mass properties by the divergence theorem: tetrahedra from the frame origin to each triangle.

struct MassProps {
  double volume = 0, area = 0;
  Vec3 centroid;                  // in the mesh frame
  std::array<double, 9> second{}; // integral of x x^T over the volume, about the centroid
};

MassProps massProperties(const Mesh& m) {
  MassProps mp;
  Vec3 first;
  std::array<double, 9> second{};
  for (const Tri& t : m.t) {
    const Vec3 a = m.v[t[0]], b = m.v[t[1]], c = m.v[t[2]];
    const double det = dot(a, cross(b, c));  // 6 * signed volume of (0, a, b, c)
    mp.volume += det / 6.0;
    mp.area += norm(cross(b - a, c - a)) / 2;
    first = first + (a + b + c) * (det / 24.0);
    // integral of x x^T over the tetrahedron (0,a,b,c) = det/120 * (a a^T + b b^T + c c^T + s s^T)
    const Vec3 s = a + b + c;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        second[i * 3 + j] += det / 120.0 * (a[i] * a[j] + b[i] * b[j] + c[i] * c[j] + s[i] * s[j]);
  }
  if (mp.volume != 0) mp.centroid = first * (1.0 / mp.volume);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) mp.second[i * 3 + j] = second[i * 3 + j] - mp.volume * mp.centroid[i] * mp.centroid[j];
  return mp;
}

// Inertia tensor about the centroid for a density: rho * (trace(C) I - C).
std::array<double, 9> inertia(const MassProps& mp, double density) {
  const double tr = mp.second[0] + mp.second[4] + mp.second[8];
  std::array<double, 9> I{};
  for (int i = 0; i < 9; ++i) I[i] = density * ((i % 4 == 0 ? tr : 0.0) - mp.second[i]);
  return I;
}

// ---------------------------------------------------------------------------------------------
// Point-triangle distance (closest point on a triangle, Ericson, Real-Time Collision Detection 5.1.5).

double distanceToTriangle(Vec3 p, Vec3 a, Vec3 b, Vec3 c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return norm(p - a);
  const Vec3 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return norm(p - b);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return norm(p - (a + ab * (d1 / (d1 - d3))));
  const Vec3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return norm(p - c);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return norm(p - (a + ac * (d2 / (d2 - d6))));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return norm(p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))));
  const double denom = va + vb + vc;
  if (denom == 0) return std::min({norm(p - a), norm(p - b), norm(p - c)});  // degenerate triangle
  return norm(p - (a + ab * (vb / denom) + ac * (vc / denom)));
}

double distanceToMesh(const Mesh& m, Vec3 local) {
  double best = HUGE_VAL;
  for (const Tri& t : m.t) best = std::min(best, distanceToTriangle(local, m.v[t[0]], m.v[t[1]], m.v[t[2]]));
  return best;
}

// ---------------------------------------------------------------------------------------------
// Point in closed mesh: ray parity along a fixed direction, accelerated by a 2D grid over the
// triangles projected on the plane orthogonal to the ray.
//
// Robustness: each edge's 2D orientation test is evaluated with its vertices in one canonical
// order (lower welded index first) and the sign flipped as needed, so the two triangles that share
// an edge always disagree on which side of it the point lies: a ray can never slip through the
// crack between them or hit both. Only an exactly zero test (the ray through an edge or vertex
// exactly) is ambiguous; then another direction is tried.

enum class Where { Outside, Inside, Near, Ambiguous };

class RayCaster {
 public:
  RayCaster(const Mesh& m, Vec3 dir, double nearDist) : mesh_(m), dir_(normalized(dir)), near_(nearDist) {
    const Vec3 helper = std::fabs(dir_.x) < 0.6 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
    e1_ = normalized(cross(dir_, helper));
    e2_ = cross(dir_, e1_);
    proj_.resize(m.v.size());
    for (size_t i = 0; i < m.v.size(); ++i) proj_[i] = {dot(m.v[i], e1_), dot(m.v[i], e2_), dot(m.v[i], dir_)};
    buildGrid();
  }

  // `q` in the mesh frame.
  Where classify(Vec3 q) const {
    const double qu = dot(q, e1_), qv = dot(q, e2_), qw = dot(q, dir_);
    const long cu = long(std::floor((qu - u0_) / cell_)), cv = long(std::floor((qv - v0_) / cell_));
    if (cu < 0 || cv < 0 || cu >= nu_ || cv >= nv_) return Where::Outside;
    const size_t cellIndex = size_t(cv) * nu_ + cu;
    int crossings = 0;
    bool ambiguous = false;
    for (uint32_t k = start_[cellIndex]; k < start_[cellIndex + 1]; ++k) {
      const Tri& t = mesh_.t[tris_[k]];
      if (isNear(q, t)) return Where::Near;
      const double s0 = edgeSide(t[1], t[2], qu, qv), s1 = edgeSide(t[2], t[0], qu, qv),
                   s2 = edgeSide(t[0], t[1], qu, qv);
      const bool pos = s0 >= 0 && s1 >= 0 && s2 >= 0, neg = s0 <= 0 && s1 <= 0 && s2 <= 0;
      if (!pos && !neg) continue;                 // the ray misses this triangle
      const double sum = s0 + s1 + s2;
      if (s0 == 0 || s1 == 0 || s2 == 0) {        // through an edge or vertex (or edge-on)
        ambiguous = true;
        continue;
      }
      const Vec3 w{proj_[t[0]].z, proj_[t[1]].z, proj_[t[2]].z};
      const double hit = (s0 * w.x + s1 * w.y + s2 * w.z) / sum;  // depth of the plane at (qu, qv)
      if (std::fabs(hit - qw) <= near_) return Where::Near;
      if (hit > qw) ++crossings;
    }
    if (ambiguous) return Where::Ambiguous;
    return crossings % 2 ? Where::Inside : Where::Outside;
  }

 private:
  // Orientation of (qu,qv) against the projected edge a->b, in canonical vertex order.
  double edgeSide(uint32_t a, uint32_t b, double qu, double qv) const {
    const bool flip = a > b;
    const Vec3 &p = proj_[flip ? b : a], &r = proj_[flip ? a : b];
    const double o = (r.x - p.x) * (qv - p.y) - (r.y - p.y) * (qu - p.x);
    return flip ? -o : o;
  }

  bool isNear(Vec3 q, const Tri& t) const {
    const Vec3 a = mesh_.v[t[0]], b = mesh_.v[t[1]], c = mesh_.v[t[2]];
    for (int i = 0; i < 3; ++i) {
      if (q[i] < std::min({a[i], b[i], c[i]}) - near_ || q[i] > std::max({a[i], b[i], c[i]}) + near_) return false;
    }
    return distanceToTriangle(q, a, b, c) <= near_;
  }

  // Triangles go into every cell that their projected bounds, grown by the near distance, touch:
  // so the query cell holds every triangle that the ray can hit and every one near the point.
  void buildGrid() {
    double ulo = HUGE_VAL, uhi = -HUGE_VAL, vlo = HUGE_VAL, vhi = -HUGE_VAL;
    for (const Vec3& p : proj_) ulo = std::min(ulo, p.x), uhi = std::max(uhi, p.x), vlo = std::min(vlo, p.y), vhi = std::max(vhi, p.y);
    if (proj_.empty()) ulo = uhi = vlo = vhi = 0;
    u0_ = ulo - 2 * near_, v0_ = vlo - 2 * near_;
    const double du = uhi - ulo + 4 * near_, dv = vhi - vlo + 4 * near_;
    const double target = std::clamp(double(mesh_.t.size()), 1.0, 4.0e6);  // about one cell per triangle
    cell_ = std::max(std::sqrt(du * dv / target), std::max(du, dv) / 4096.0);
    if (!(cell_ > 0)) cell_ = 1;
    nu_ = std::max(1L, long(std::ceil(du / cell_))), nv_ = std::max(1L, long(std::ceil(dv / cell_)));
    std::vector<uint32_t> count(size_t(nu_) * nv_ + 1, 0);
    auto forCells = [&](const Tri& t, auto&& fn) {
      double a0 = HUGE_VAL, a1 = -HUGE_VAL, b0 = HUGE_VAL, b1 = -HUGE_VAL;
      for (uint32_t i : t) a0 = std::min(a0, proj_[i].x), a1 = std::max(a1, proj_[i].x), b0 = std::min(b0, proj_[i].y), b1 = std::max(b1, proj_[i].y);
      const long i0 = std::clamp(long(std::floor((a0 - near_ - u0_) / cell_)), 0L, nu_ - 1);
      const long i1 = std::clamp(long(std::floor((a1 + near_ - u0_) / cell_)), 0L, nu_ - 1);
      const long j0 = std::clamp(long(std::floor((b0 - near_ - v0_) / cell_)), 0L, nv_ - 1);
      const long j1 = std::clamp(long(std::floor((b1 + near_ - v0_) / cell_)), 0L, nv_ - 1);
      for (long j = j0; j <= j1; ++j)
        for (long i = i0; i <= i1; ++i) fn(size_t(j) * nu_ + i);
    };
    for (const Tri& t : mesh_.t) forCells(t, [&](size_t c) { ++count[c + 1]; });
    start_.assign(count.size(), 0);
    for (size_t c = 1; c < count.size(); ++c) start_[c] = start_[c - 1] + count[c];
    tris_.resize(start_.back());
    std::vector<uint32_t> fill(start_.begin(), start_.end() - 1);
    for (uint32_t i = 0; i < mesh_.t.size(); ++i) forCells(mesh_.t[i], [&](size_t c) { tris_[fill[c]++] = i; });
  }

  const Mesh& mesh_;
  Vec3 dir_, e1_, e2_;
  double near_;
  std::vector<Vec3> proj_;  // (u, v, depth along the ray) per vertex
  double u0_ = 0, v0_ = 0, cell_ = 1;
  long nu_ = 1, nv_ = 1;
  std::vector<uint32_t> start_, tris_;
};

// Point-in-mesh with fallback directions, built on first need.
class InsideTest {
 public:
  InsideTest(const Mesh& m, double nearDist) : mesh_(m), near_(nearDist) {}

  // `world` in world space. Near: within the near distance of a face (or hopelessly ambiguous).
  Where classify(Vec3 world) {
    const Vec3 q = world - mesh_.offset;
    if (!mesh_.localBox.inflated(near_).contains(q)) return Where::Outside;
    static const Vec3 kDirs[] = {{0.5413, 0.3289, 0.7741}, {-0.2718, 0.8371, 0.4747}, {0.6931, -0.5772, 0.4319},
                                 {-0.1414, -0.2236, 0.9643}};
    for (size_t i = 0; i < std::size(kDirs); ++i) {
      if (casters_.size() <= i) casters_.push_back(std::make_unique<RayCaster>(mesh_, kDirs[i], near_));
      const Where w = casters_[i]->classify(q);
      if (w != Where::Ambiguous) return w;
      ++ambiguousRays;
    }
    return Where::Near;
  }
  size_t ambiguousRays = 0;

 private:
  const Mesh& mesh_;
  double near_;
  std::vector<std::unique_ptr<RayCaster>> casters_;
};

// ---------------------------------------------------------------------------------------------
// A uniform 3D grid of boxes (pieces, triangles): which boxes touch each cell.

class BoxGrid {
 public:
  BoxGrid(const std::vector<Box>& boxes, const Box& domain, double targetCells) : domain_(domain) {
    const Vec3 ext = domain.hi - domain.lo;
    const double vol = std::max(ext.x, 1e-300) * std::max(ext.y, 1e-300) * std::max(ext.z, 1e-300);
    double cell = std::cbrt(vol / std::max(targetCells, 1.0));
    cell = std::max(cell, maxAbs(ext) / 512.0);
    for (int i = 0; i < 3; ++i) n_[i] = std::max(1L, long(std::ceil(ext[i] / cell)));
    for (int i = 0; i < 3; ++i) size_[i] = ext[i] > 0 ? ext[i] / double(n_[i]) : 1.0;
    std::vector<uint32_t> count(cells() + 1, 0);
    for (const Box& b : boxes) forCells(b, [&](size_t c) { ++count[c + 1]; });
    start_.assign(count.size(), 0);
    for (size_t c = 1; c < count.size(); ++c) start_[c] = start_[c - 1] + count[c];
    items_.resize(start_.back());
    std::vector<uint32_t> fill(start_.begin(), start_.end() - 1);
    for (uint32_t i = 0; i < boxes.size(); ++i) forCells(boxes[i], [&](size_t c) { items_[fill[c]++] = i; });
  }
  size_t cells() const { return size_t(n_[0]) * n_[1] * n_[2]; }
  size_t cellOf(Vec3 p) const {
    long c[3];
    for (int i = 0; i < 3; ++i) c[i] = std::clamp(long(std::floor((p[i] - domain_.lo[i]) / size_[i])), 0L, n_[i] - 1);
    return (size_t(c[2]) * n_[1] + c[1]) * n_[0] + c[0];
  }
  std::pair<const uint32_t*, const uint32_t*> itemsIn(size_t cell) const {
    return {items_.data() + start_[cell], items_.data() + start_[cell + 1]};
  }
  template <class Fn>
  void forCells(const Box& b, Fn&& fn) const {
    long lo[3], hi[3];
    for (int i = 0; i < 3; ++i) {
      lo[i] = std::clamp(long(std::floor((b.lo[i] - domain_.lo[i]) / size_[i])), 0L, n_[i] - 1);
      hi[i] = std::clamp(long(std::floor((b.hi[i] - domain_.lo[i]) / size_[i])), 0L, n_[i] - 1);
    }
    for (long z = lo[2]; z <= hi[2]; ++z)
      for (long y = lo[1]; y <= hi[1]; ++y)
        for (long x = lo[0]; x <= hi[0]; ++x) fn((size_t(z) * n_[1] + y) * n_[0] + x);
  }

 private:
  Box domain_;
  long n_[3] = {1, 1, 1};
  double size_[3] = {1, 1, 1};
  std::vector<uint32_t> start_, items_;
};

// ---------------------------------------------------------------------------------------------
// Sampling: overlap and coverage.

struct SampleStats {
  size_t samples = 0, skippedNearSurface = 0, insideReference = 0, overlapping = 0, uncovered = 0,
         outsideReference = 0, ambiguousRays = 0;
};

SampleStats sampleVolumes(const std::vector<Mesh>& pieces, const Mesh& ref, const Box& domain, size_t n,
                          uint64_t seed, double nearDist, Report& report) {
  SampleStats st;
  st.samples = n;
  std::vector<InsideTest> tests;
  std::vector<Box> boxes;
  for (const Mesh& p : pieces) tests.emplace_back(p, nearDist), boxes.push_back(p.worldBox.inflated(nearDist));
  InsideTest refTest(ref, nearDist);
  const BoxGrid grid(boxes, domain, std::max(8.0 * pieces.size(), 1.0));

  // Deterministic: mt19937_64's sequence is fixed by the standard; the conversion to [0,1) is ours.
  std::mt19937_64 rng(seed);
  auto uniform = [&] { return double(rng() >> 11) * 0x1.0p-53; };
  std::vector<uint32_t> inside;
  for (size_t s = 0; s < n; ++s) {
    const Vec3 e = domain.hi - domain.lo;
    const Vec3 p{domain.lo.x + e.x * uniform(), domain.lo.y + e.y * uniform(), domain.lo.z + e.z * uniform()};
    const Where inRef = refTest.classify(p);
    bool near = inRef == Where::Near;
    inside.clear();
    const auto [b, end] = grid.itemsIn(grid.cellOf(p));
    for (const uint32_t* it = b; it != end && !near; ++it) {
      if (!boxes[*it].contains(p)) continue;
      const Where w = tests[*it].classify(p);
      if (w == Where::Near) near = true;
      else if (w == Where::Inside) inside.push_back(*it);
    }
    if (near) { ++st.skippedNearSurface; continue; }
    const bool r = inRef == Where::Inside;
    st.insideReference += r;
    if (inside.size() >= 2) {
      ++st.overlapping;
      std::string names;
      for (uint32_t i : inside) names += (names.empty() ? "" : " and ") + pieces[i].name;
      report.fail("overlap", names + " both contain " + fmt(p));
    }
    if (r && inside.empty()) {
      ++st.uncovered;
      report.warn("uncovered_points", "inside the reference, in no piece: " + fmt(p));
    }
    if (!r && !inside.empty()) {
      ++st.outsideReference;
      report.warn("points_outside_reference", pieces[inside[0]].name + " contains " + fmt(p) + ", outside the reference");
    }
  }
  for (const auto& t : tests) st.ambiguousRays += t.ambiguousRays;
  st.ambiguousRays += refTest.ambiguousRays;
  return st;
}

// ---------------------------------------------------------------------------------------------
// Contacts: the face area that two pieces share, measured from their triangles.

struct Contact {
  double area = 0;
  Vec3 centroidSum;  // area-weighted
  Vec3 normalSum;    // area-weighted outward normal of the lower-numbered piece
};

struct TriInfo {
  uint32_t piece;
  Vec3 a, b, c, n;  // world corners, unit normal
  double offset;    // plane: dot(n, x) = offset
};

// Area of the convex polygon `poly` clipped to the counter-clockwise triangle `tri` (2D), the
// centroid of the clipped part and the clipped polygon.
double clippedArea(std::vector<std::array<double, 2>> poly, const std::array<std::array<double, 2>, 3>& tri,
                   std::array<double, 2>& centroid, std::vector<std::array<double, 2>>& clipped) {
  for (int e = 0; e < 3 && !poly.empty(); ++e) {
    const auto p = tri[e], q = tri[(e + 1) % 3];
    auto side = [&](const std::array<double, 2>& x) { return (q[0] - p[0]) * (x[1] - p[1]) - (q[1] - p[1]) * (x[0] - p[0]); };
    std::vector<std::array<double, 2>> out;
    for (size_t i = 0; i < poly.size(); ++i) {
      const auto& s = poly[i];
      const auto& t = poly[(i + 1) % poly.size()];
      const double ss = side(s), st = side(t);
      if (ss >= 0) out.push_back(s);
      if ((ss >= 0) != (st >= 0)) {
        const double f = ss / (ss - st);
        out.push_back({s[0] + (t[0] - s[0]) * f, s[1] + (t[1] - s[1]) * f});
      }
    }
    poly = std::move(out);
  }
  double area2 = 0, cx = 0, cy = 0;
  for (size_t i = 0; i < poly.size(); ++i) {
    const auto& s = poly[i];
    const auto& t = poly[(i + 1) % poly.size()];
    const double c = s[0] * t[1] - t[0] * s[1];
    area2 += c, cx += (s[0] + t[0]) * c, cy += (s[1] + t[1]) * c;
  }
  clipped = poly;
  if (area2 == 0) return 0;
  centroid = {cx / (3 * area2), cy / (3 * area2)};
  return std::fabs(area2) / 2;
}

std::map<std::pair<uint32_t, uint32_t>, Contact> measureContacts(const std::vector<Mesh>& pieces, const Box& domain,
                                                                 double planeTol) {
  std::vector<TriInfo> tris;
  std::vector<Box> boxes;  // per triangle, grown by the plane tolerance
  size_t total = 0;
  for (const Mesh& m : pieces) total += m.t.size();
  tris.reserve(total), boxes.reserve(total);
  for (uint32_t p = 0; p < pieces.size(); ++p) {
    const Mesh& m = pieces[p];
    for (const Tri& t : m.t) {
      TriInfo ti{p, m.v[t[0]] + m.offset, m.v[t[1]] + m.offset, m.v[t[2]] + m.offset, {}, 0};
      const Vec3 c = cross(ti.b - ti.a, ti.c - ti.a);
      if (norm(c) == 0) continue;
      ti.n = normalized(c);
      ti.offset = dot(ti.n, ti.a + ti.b + ti.c) / 3;
      Box box;
      box.add(ti.a), box.add(ti.b), box.add(ti.c);
      tris.push_back(ti);
      boxes.push_back(box.inflated(planeTol));
    }
  }
  const BoxGrid grid(boxes, domain, 2.0 * tris.size());
  std::map<std::pair<uint32_t, uint32_t>, Contact> contacts;
  for (size_t cell = 0; cell < grid.cells(); ++cell) {
    const auto [begin, end] = grid.itemsIn(cell);
    for (const uint32_t* i = begin; i != end; ++i) {
      for (const uint32_t* j = i + 1; j != end; ++j) {
        const TriInfo &A = tris[*i], &B = tris[*j];
        const Box &boxA = boxes[*i], &boxB = boxes[*j];
        if (A.piece == B.piece || dot(A.n, B.n) > -0.999 || !boxA.overlaps(boxB)) continue;
        // Each pair is measured once: in the cell holding the low corner of the boxes' overlap.
        const Vec3 lo{std::max(boxA.lo.x, boxB.lo.x), std::max(boxA.lo.y, boxB.lo.y), std::max(boxA.lo.z, boxB.lo.z)};
        if (grid.cellOf(lo) != cell) continue;
        // Project both onto A's plane (A is counter-clockwise in the basis e1, e2 with e1 x e2 = nA)
        // and clip. Coplanar means: B's plane is within the tolerance of A's over the overlap. Not
        // over all of B: a small triangle's plane, tilted by rounding, drifts off over a large one.
        const Vec3 e1 = normalized(A.b - A.a), e2 = cross(A.n, e1);
        auto uv = [&](Vec3 x) { return std::array<double, 2>{dot(x - A.a, e1), dot(x - A.a, e2)}; };
        std::array<double, 2> c2{};
        std::vector<std::array<double, 2>> overlap;
        const double area = clippedArea({uv(B.a), uv(B.b), uv(B.c)}, {uv(A.a), uv(A.b), uv(A.c)}, c2, overlap);
        if (area <= 0) continue;
        const bool coplanar = std::all_of(overlap.begin(), overlap.end(), [&](const std::array<double, 2>& q) {
          return std::fabs(dot(B.n, A.a + e1 * q[0] + e2 * q[1]) - B.offset) <= planeTol;
        });
        if (!coplanar) continue;
        const bool aFirst = A.piece < B.piece;
        Contact& ct = contacts[{std::min(A.piece, B.piece), std::max(A.piece, B.piece)}];
        ct.area += area;
        ct.centroidSum = ct.centroidSum + (A.a + e1 * c2[0] + e2 * c2[1]) * area;
        ct.normalSum = ct.normalSum + (aFirst ? A.n : B.n) * area;
      }
    }
  }
  return contacts;
}

// ---------------------------------------------------------------------------------------------
// The checks on fracture.json.

Vec3 jsonVec3(const Json& j) {
  if (!j.is_array() || j.size() != 3) throw ReadError{"expected [x, y, z]"};
  return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
}

struct PieceResult {
  Topology topo;
  MassProps mass;
};

// Topology and mass properties of every piece, with their counts in the report.
std::vector<PieceResult> checkPieceMeshes(const std::vector<Mesh>& pieces, Report& report) {
  std::vector<PieceResult> results;
  Json counts = {{"pieces", pieces.size()}, {"triangles", 0}, {"repeated_index", 0}, {"same_position", 0},
                 {"zero_area", 0}, {"boundary_edges", 0}, {"non_manifold_edges", 0},
                 {"misoriented_edges", 0}, {"pinched_vertices", 0}, {"not_outward", 0}, {"bad_pieces", 0}};
  auto add = [&](const char* k, size_t v) { counts[k] = counts[k].get<size_t>() + v; };
  for (const Mesh& m : pieces) {
    PieceResult r{checkTopology(m, report), massProperties(m)};
    const Topology& t = r.topo;
    const bool outward = r.mass.volume > 0;
    if (!outward) report.fail("orientation", m.name + ": signed volume " + fmt(r.mass.volume) + " is not positive");
    add("triangles", m.t.size());
    add("repeated_index", t.repeatedIndex), add("same_position", t.samePosition), add("zero_area", t.zeroArea);
    add("boundary_edges", t.boundaryEdges), add("non_manifold_edges", t.nonManifoldEdges);
    add("misoriented_edges", t.misorientedEdges), add("pinched_vertices", t.pinchedVertices);
    add("not_outward", !outward);
    add("bad_pieces", !t.closedManifold() || !outward || t.repeatedIndex || t.samePosition || t.zeroArea);
    results.push_back(r);
  }
  report.counts["pieces"] = counts;
  return results;
}

// Largest deviations from fracture.json, for the report.
struct JsonDeviation {
  double volume = 0, pivot = 0, centroid = 0, inertia = 0;  // relative, /diag, /diag, relative
};

JsonDeviation checkPiecesAgainstJson(const std::vector<Mesh>& pieces, const std::vector<PieceResult>& results,
                                     const Json& doc, double diag, Report& report) {
  JsonDeviation dev;
  const Json& jp = doc.at("pieces");
  if (jp.size() != pieces.size())
    report.fail("json", "fracture.json lists " + std::to_string(jp.size()) + " pieces, fragments.glb has " + std::to_string(pieces.size()));
  double density = 0;
  if (doc.contains("settings") && doc["settings"].contains("density")) density = doc["settings"]["density"].get<double>();
  for (size_t i = 0; i < std::min(jp.size(), pieces.size()); ++i) {
    const Json& j = jp[i];
    const Mesh& m = pieces[i];
    const MassProps& mp = results[i].mass;
    const std::string& name = m.name;
    if (j.at("id").get<long>() != long(i) || j.at("name").get<std::string>() != pieceName(i))
      report.fail("json", "entry " + std::to_string(i) + " has id/name " + j.at("id").dump() + "/" + j.at("name").dump());
    if (j.at("triangles").get<size_t>() != m.t.size())
      report.fail("json", name + ": triangles " + j.at("triangles").dump() + " in json, " + std::to_string(m.t.size()) + " in glb");
    const bool closed = results[i].topo.closed();
    if (j.at("closed").get<bool>() != closed)
      report.fail("json", name + ": json says closed=" + j.at("closed").dump() + ", the mesh is " + (closed ? "closed" : "not closed"));
    // What rounding the vertices to float can change: the surface moved by half an ulp.
    const double rounding = 2 * mp.area * 0x1.0p-24 * std::max(maxAbs(m.worldBox.lo), maxAbs(m.worldBox.hi));
    const double vj = j.at("volume").get<double>();
    dev.volume = std::max(dev.volume, std::fabs(vj - mp.volume) / std::fabs(vj));
    if (std::fabs(vj - mp.volume) > 1e-6 * std::fabs(vj) + rounding)
      report.fail("piece_volume", name + ": json volume " + fmt(vj) + ", mesh " + fmt(mp.volume));
    if (density > 0 && j.contains("mass")) {
      const double mj = j["mass"].get<double>();
      if (std::fabs(mj - density * vj) > 1e-9 * std::fabs(mj))
        report.fail("piece_mass", name + ": mass " + fmt(mj) + " != density * volume " + fmt(density * vj));
    }
    const Vec3 com = jsonVec3(j.at("center_of_mass"));
    const double comTol = 1e-6 * diag + 2 * 0x1.0p-24 * maxAbs(com);  // translation is a float
    dev.pivot = std::max(dev.pivot, norm(m.offset - com) / diag);
    if (mp.volume > 0) dev.centroid = std::max(dev.centroid, norm(m.offset + mp.centroid - com) / diag);
    if (norm(m.offset - com) > comTol)
      report.fail("pivot", name + ": node translation " + fmt(m.offset) + " != center_of_mass " + fmt(com));
    if (mp.volume > 0 && norm(m.offset + mp.centroid - com) > comTol)
      report.fail("center_of_mass", name + ": centroid " + fmt(m.offset + mp.centroid) + " != json " + fmt(com));
    if (density > 0 && j.contains("inertia") && mp.volume > 0) {
      const auto I = inertia(mp, density);
      double diff = 0, size = 0;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
          const double x = j["inertia"].at(r).at(c).get<double>();
          diff = std::max(diff, std::fabs(x - I[r * 3 + c]));
          size = std::max(size, std::fabs(I[r * 3 + c]));
        }
      dev.inertia = std::max(dev.inertia, diff / size);
      if (diff > (1e-6 + rounding / mp.volume) * size)
        report.fail("inertia", name + ": json inertia differs from the mesh's by " + fmt(diff) + " (largest entry " + fmt(size) + ")");
    }
  }
  return dev;
}

struct BondStats {
  size_t bonds = 0, contacts = 0, unbondedContacts = 0, unbondedClear = 0;
  double unbondedArea = 0;
  double maxAreaError = 0, maxCentroidError = 0, maxNormalAngle = 0;  // against the measured contacts
};

BondStats checkBonds(const std::vector<Mesh>& pieces, const Json& bonds,
                     const std::map<std::pair<uint32_t, uint32_t>, Contact>& contacts, double diag, Report& report) {
  BondStats st;
  st.bonds = bonds.size();
  st.contacts = contacts.size();
  std::map<std::pair<long, long>, size_t> seen;
  for (size_t k = 0; k < bonds.size(); ++k) {
    const Json& b = bonds[k];
    const long a = b.at("a").get<long>(), c = b.at("b").get<long>();
    const std::string tag = "bond " + std::to_string(k) + " (" + std::to_string(a) + "," + std::to_string(c) + ")";
    if (a < 0 || c < 0 || a >= long(pieces.size()) || c >= long(pieces.size())) {
      report.fail("bond", tag + ": names a piece that does not exist");
      continue;
    }
    if (a >= c) {
      report.fail("bond", tag + ": a >= b");  // the normal's sense is undefined: nothing more to check
      continue;
    }
    if (seen[{a, c}]++) report.fail("bond", tag + ": duplicate bond");
    const double area = b.at("area").get<double>();
    if (!(area > 0) || !std::isfinite(area)) report.fail("bond", tag + ": area " + fmt(area));
    const Vec3 n = jsonVec3(b.at("normal")), centroid = jsonVec3(b.at("centroid"));
    if (std::fabs(norm(n) - 1) > 1e-6) report.fail("bond", tag + ": normal length " + fmt(norm(n)));

    // Against the contact measured from the two meshes (exact for a clean fracture up to float
    // rounding: relative area error < 1e-5 and centroid error < 1e-7 * diag were seen on faces
    // bigger than slivers; tiny faces reach 1e-3 relative, so a clear case is both relatively
    // and absolutely large).
    const auto it = contacts.find({uint32_t(a), uint32_t(c)});
    const Contact* ct = it == contacts.end() ? nullptr : &it->second;
    const Vec3 measuredCentroid = ct ? ct->centroidSum * (1 / ct->area) : Vec3{};
    if (!ct) {
      report.fail("bond_contact", tag + ": the pieces share no face area (bond area " + fmt(area) + ")");
    } else {
      const Vec3 mn = normalized(ct->normalSum);
      const double areaErr = std::fabs(ct->area - area), centroidErr = norm(measuredCentroid - centroid);
      const double angle = std::acos(std::clamp(dot(mn, n), -1.0, 1.0));
      st.maxAreaError = std::max(st.maxAreaError, areaErr / area);
      st.maxCentroidError = std::max(st.maxCentroidError, centroidErr / diag);
      st.maxNormalAngle = std::max(st.maxNormalAngle, angle);
      // A flip is clear (cosine -1); a contact over several planes (merged pieces) legitimately has
      // a mean normal some way from any one face's, hence the generous -0.5.
      if (dot(mn, n) < -0.5) report.fail("bond_normal", tag + ": normal " + fmt(n) + " points from b to a (measured " + fmt(mn) + ")");
      else if (angle > 1e-2) report.warn("bond_normal_deviation", tag + ": " + fmt(angle) + " rad from the measured contact normal");
      const std::string areas = tag + ": area " + fmt(area) + ", the pieces share " + fmt(ct->area);
      if (areaErr > 1e-2 * area && areaErr > 1e-6 * diag * diag) report.fail("bond_area", areas);
      else if (areaErr > 1e-3 * area && areaErr > 1e-9 * diag * diag) report.warn("bond_area_mismatch", areas);
      const std::string centroids = tag + ": centroid " + fmt(centroid) + ", of the shared face " + fmt(measuredCentroid);
      if (centroidErr > 1e-3 * diag) report.fail("bond_centroid", centroids);
      else if (centroidErr > 1e-5 * diag) report.warn("bond_centroid_mismatch", centroids);
    }

    // The centroid on both surfaces. A non-convex shared face can have its centroid outside
    // itself: that passes when the centroid is the shared face's own (within the same 1e-5 * diag).
    const double tol = 1e-5 * diag;
    for (long p : {a, c}) {
      const double d = distanceToMesh(pieces[p], centroid - pieces[p].offset);
      if (d <= tol) continue;
      if (ct && norm(measuredCentroid - centroid) <= tol) {
        report.warn("bond_centroid_off_face", tag + ": centroid of a non-convex shared face, " + fmt(d) + " from " + pieces[p].name);
      } else {
        report.fail("bond_centroid", tag + ": centroid " + fmt(centroid) + " is " + fmt(d) + " from the surface of " + pieces[p].name);
      }
    }
  }
  for (const auto& [pair, ct] : contacts) {
    if (seen.count({long(pair.first), long(pair.second)})) continue;
    ++st.unbondedContacts;
    st.unbondedArea += ct.area;
    const std::string what = pieces[pair.first].name + " and " + pieces[pair.second].name + " share " + fmt(ct.area) +
                             " of face around " + fmt(ct.centroidSum * (1 / ct.area)) + " but have no bond";
    if (ct.area > 1e-6 * diag * diag) {
      ++st.unbondedClear;
      report.fail("missing_bond", what);
    } else {
      report.warn("small_unbonded_contact", what);
    }
  }
  return st;
}

// ---------------------------------------------------------------------------------------------

struct Args {
  std::string dir, reference;
  size_t samples = 20000;
  uint64_t seed = 1;
};

std::optional<Args> parseArgs(int argc, char** argv) {
  Args a;
  std::vector<std::string> pos;
  for (int i = 1; i < argc; ++i) {
    const std::string s = argv[i];
    if ((s == "--samples" || s == "--seed") && i + 1 < argc) {
      (s == "--samples" ? a.samples : a.seed) = std::stoull(argv[++i]);
    } else if (s.rfind("--", 0) == 0) {
      return std::nullopt;
    } else {
      pos.push_back(s);
    }
  }
  if (pos.size() != 2) return std::nullopt;
  a.dir = pos[0], a.reference = pos[1];
  return a;
}

int run(const Args& args) {
  const auto t0 = std::chrono::steady_clock::now();
  Json timing = Json::object();  // seconds per phase
  auto lap = [&, last = t0](const char* phase) mutable {
    const auto now = std::chrono::steady_clock::now();
    timing[phase] = std::chrono::duration<double>(now - last).count();
    last = now;
  };
  Report report;
  Json doc;
  {
    std::ifstream in(args.dir + "/fracture.json");
    if (!in) throw ReadError{args.dir + "/fracture.json: cannot open"};
    try { doc = Json::parse(in); } catch (const std::exception& e) { throw ReadError{std::string("fracture.json: ") + e.what()}; }
  }
  if (doc.value("format", "") != "dawnforge.fracture" || doc.value("version", 0) != 1)
    report.fail("json", "format/version is not dawnforge.fracture/1");
  std::vector<Mesh> pieces = loadPieces(args.dir + "/fragments.glb", report);
  Mesh ref = loadReference(args.reference);
  lap("read");

  Box domain = ref.worldBox;
  for (const Mesh& p : pieces) domain.add(p.worldBox);
  const double diag = domain.diagonal();

  // The reference must be a closed, outward mesh for its volume and inside test to mean anything.
  Report refReport;
  const Topology refTopo = checkTopology(ref, refReport);
  const MassProps refMass = massProperties(ref);
  if (!refTopo.closedManifold() || refMass.volume <= 0)
    throw ReadError{args.reference + ": the reference mesh is not closed, manifold and outward: " + refReport.failureList().dump()};

  // Per piece: topology and mass properties.
  const std::vector<PieceResult> results = checkPieceMeshes(pieces, report);
  double sumVolume = 0;
  for (const PieceResult& r : results) sumVolume += r.mass.volume;

  // Volumes.
  const double relErr = std::fabs(sumVolume - refMass.volume) / refMass.volume;
  report.counts["volume"] = {{"reference", refMass.volume}, {"pieces_sum", sumVolume}, {"relative_error", relErr},
                             {"json", doc.value("volume", 0.0)}};
  if (relErr > 1e-6) report.fail("volume_sum", "pieces add up to " + fmt(sumVolume) + ", the reference has " + fmt(refMass.volume) + " (relative error " + fmt(relErr) + ")");
  const JsonDeviation dev = checkPiecesAgainstJson(pieces, results, doc, diag, report);
  report.counts["json_deviation"] = {{"max_volume_relative", dev.volume}, {"max_pivot_per_diag", dev.pivot},
                                     {"max_centroid_per_diag", dev.centroid}, {"max_inertia_relative", dev.inertia}};
  lap("pieces");

  // Overlap and coverage.
  const double nearDist = 1e-6 * diag;
  const SampleStats ss = sampleVolumes(pieces, ref, domain, args.samples, args.seed, nearDist, report);
  const double denom = std::max<size_t>(ss.insideReference, 1);
  report.counts["sampling"] = {{"samples", ss.samples}, {"seed", args.seed}, {"skipped_near_surface", ss.skippedNearSurface},
                               {"ambiguous_rays", ss.ambiguousRays}, {"inside_reference", ss.insideReference},
                               {"overlapping", ss.overlapping}, {"uncovered", ss.uncovered},
                               {"outside_reference", ss.outsideReference},
                               {"uncovered_fraction", ss.uncovered / denom}, {"outside_fraction", ss.outsideReference / denom}};
  lap("sampling");
  if (ss.insideReference == 0) report.fail("coverage", "no sample fell inside the reference");
  if (ss.uncovered / denom > 1e-3) report.fail("coverage", fmt(ss.uncovered / denom) + " of the points inside the reference are in no piece");
  if (ss.outsideReference / denom > 1e-3) report.fail("coverage", "points in pieces but outside the reference: " + fmt(ss.outsideReference / denom) + " of those inside it");

  // Bonds.
  const double planeTol = 1e-6 * diag + 4 * 0x1.0p-24 * std::max(maxAbs(domain.lo), maxAbs(domain.hi));
  const auto contacts = measureContacts(pieces, domain, planeTol);
  lap("contacts");
  const BondStats bs = checkBonds(pieces, doc.at("bonds"), contacts, diag, report);
  report.counts["bonds"] = {{"bonds", bs.bonds}, {"touching_pairs", bs.contacts}, {"unbonded_contacts", bs.unbondedContacts},
                            {"unbonded_clear", bs.unbondedClear}, {"unbonded_area", bs.unbondedArea},
                            {"max_area_relative_error", bs.maxAreaError}, {"max_centroid_error_per_diag", bs.maxCentroidError},
                            {"max_normal_angle", bs.maxNormalAngle}};
  lap("bonds");

  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  Json out = {{"fracture", args.dir}, {"reference", args.reference},
              {"reference_triangles", ref.t.size()}, {"diagonal", diag}, {"ok", !report.failed()}};
  for (const auto& [k, v] : report.counts.items()) out[k] = v;
  out["failure_counts"] = report.failureCounts();
  out["failures"] = report.failureList();
  out["warnings"] = report.warnings;
  out["seconds"] = seconds;
  out["timing"] = timing;
  std::printf("%s\n", out.dump(2).c_str());
  return report.failed() ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::optional<Args> args;
  try { args = parseArgs(argc, argv); } catch (const std::exception&) {}  // a number that is not one
  if (!args) {
    std::fprintf(stderr, "usage: fracture_check FRACTURE_DIR REFERENCE_MESH [--samples N] [--seed S]\n");
    return 2;
  }
  try {
    return run(*args);
  } catch (const ReadError& e) {
    std::printf("%s\n", Json{{"ok", false}, {"error", e.what}}.dump(2).c_str());
    return 2;
  } catch (const std::exception& e) {  // malformed json fields, out-of-range node references
    std::printf("%s\n", Json{{"ok", false}, {"error", std::string("cannot read: ") + e.what()}}.dump(2).c_str());
    return 2;
  }
}
