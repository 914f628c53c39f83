// Mesh import: OBJ through tinyobjloader, glTF 2.0 / GLB through tinygltf (they keep what
// dawnforge writes: material IDs in COLOR_0, piece IDs, node names), OFF through CGAL's
// reader (import_off.cpp), every other format through Assimp (import_assimp.cpp).
#include "import_assimp.hpp"
#include "import_off.hpp"
#include "mesh_wire.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/import.hpp>
#include <dawnforge/core/isolate.hpp>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <nlohmann/json.hpp>
#include <tiny_gltf.h>
#include <tiny_obj_loader.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <sstream>

namespace dawnforge {

namespace fs = std::filesystem;

namespace {

// ---------------------------------------------------------------- OBJ

// tinyobjloader reads an unparsable number as 0 and silently drops a face with a bad
// vertex index, so the `v` and `f` lines are checked first, with line numbers.
void checkObjLines(const fs::path& file, const std::string& name) {
    std::ifstream in(file, std::ios::binary);
    std::string line;
    std::size_t lineNo = 0;
    long long vertices = 0;
    while (std::getline(in, line)) {
        ++lineNo;
        std::istringstream tokens(line);
        std::string keyword;
        tokens >> keyword;
        if (keyword == "v") {
            for (int k = 0; k < 3; ++k) {
                std::string t;
                if (!(tokens >> t))
                    throw InputError(format("{}: line {}: a vertex needs three coordinates", name, lineNo));
                char* end = nullptr;
                const double x = std::strtod(t.c_str(), &end);
                if (end != t.c_str() + t.size())
                    throw InputError(format("{}: line {}: '{}' is not a number", name, lineNo, t.substr(0, 32)));
                if (!std::isfinite(x) || std::fabs(x) > std::numeric_limits<float>::max())
                    throw InputError(format("{}: line {}: vertex {} has a non-finite coordinate ({})", name,
                                            lineNo, vertices + 1, t.substr(0, 32)));
            }
            ++vertices;
        } else if (keyword == "f") {
            std::string t;
            while (tokens >> t) {
                char* end = nullptr;
                const long long i = std::strtoll(t.c_str(), &end, 10);
                if (end == t.c_str() || (*end != '\0' && *end != '/'))
                    throw InputError(format("{}: line {}: '{}' is not a vertex reference", name, lineNo,
                                            t.substr(0, 32)));
                if (i == 0 || i > vertices || i < -vertices)
                    throw InputError(format("{}: line {}: a face uses vertex {} but only {} vertices come before it",
                                            name, lineNo, i, vertices));
            }
        }
    }
}

// Splits a simple polygon (corners in order, planar or nearly so) into corners.size() - 2
// triangles of local corner indices, wound as the polygon is, by ear clipping in the
// plane of its Newell normal: right for non-convex faces, where a fan overlaps itself.
// Only reflex corners can lie inside an ear, so a convex face costs O(n). A degenerate or
// self-intersecting polygon still gets n - 2 triangles (what is left, as a fan).
std::vector<std::array<std::uint32_t, 3>> triangulatePolygon(std::span<const glm::dvec3> corners) {
    const auto n = static_cast<std::uint32_t>(corners.size());
    std::vector<std::array<std::uint32_t, 3>> triangles;
    if (n < 3) return triangles;
    triangles.reserve(n - 2);
    std::vector<std::uint32_t> next(n), prev(n);  // the corners not yet clipped, as a ring
    for (std::uint32_t i = 0; i < n; ++i) {
        next[i] = (i + 1) % n;
        prev[i] = (i + n - 1) % n;
    }
    std::uint32_t remaining = n, cur = 0;
    glm::dvec3 normal(0.0);  // Newell's method: right for non-convex and slightly warped polygons
    for (std::uint32_t i = 0; i < n; ++i) {
        const glm::dvec3& a = corners[i];
        const glm::dvec3& b = corners[next[i]];
        normal += glm::dvec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
    }
    const double length = glm::length(normal);
    if (n > 3 && length > 0.0 && std::isfinite(length)) {
        // A basis (u, v) of the plane with u x v = normal: the polygon runs counter-clockwise in it.
        const glm::dvec3 w = normal / length;
        const glm::dvec3 helper = std::fabs(w.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
        const glm::dvec3 u = glm::normalize(glm::cross(helper, w));
        const glm::dvec3 v = glm::cross(w, u);
        std::vector<glm::dvec2> p(n);
        for (std::uint32_t i = 0; i < n; ++i)
            p[i] = {glm::dot(corners[i] - corners[0], u), glm::dot(corners[i] - corners[0], v)};
        auto cross = [](glm::dvec2 a, glm::dvec2 b, glm::dvec2 c) {
            return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
        };
        auto convex = [&](std::uint32_t i) { return cross(p[prev[i]], p[i], p[next[i]]) > 0.0; };
        std::vector<char> reflex(n, 0), clipped(n, 0);  // reflex: turns right or goes straight
        std::vector<std::uint32_t> reflexCorners;
        for (std::uint32_t i = 0; i < n; ++i)
            if (!convex(i)) {
                reflex[i] = 1;
                reflexCorners.push_back(i);
            }
        auto isEar = [&](std::uint32_t i) {
            if (reflex[i]) return false;
            const glm::dvec2 a = p[prev[i]], b = p[i], c = p[next[i]];
            for (std::uint32_t j : reflexCorners) {  // no reflex corner inside the ear or on its border
                if (!reflex[j] || clipped[j] || j == prev[i] || j == next[i]) continue;
                const glm::dvec2 q = p[j];
                if (q == a || q == b || q == c) continue;  // a repeated point (a bridged hole) touches, not blocks
                if (cross(a, b, q) >= 0.0 && cross(b, c, q) >= 0.0 && cross(c, a, q) >= 0.0) return false;
            }
            return true;
        };
        std::uint32_t sinceClip = 0;
        while (remaining > 3 && sinceClip < remaining) {
            if (!isEar(cur)) {
                cur = next[cur];
                ++sinceClip;
                continue;
            }
            const std::uint32_t a = prev[cur], c = next[cur];
            triangles.push_back({a, cur, c});
            next[a] = c;
            prev[c] = a;
            clipped[cur] = 1;
            --remaining;
            for (std::uint32_t x : {a, c})
                if (reflex[x] && convex(x)) reflex[x] = 0;
            cur = a;  // the corner before may have become an ear
            sinceClip = 0;
        }
    }
    for (std::uint32_t k = 0, x = next[cur]; k + 2 < remaining; ++k, x = next[x])
        triangles.push_back({cur, x, next[x]});
    return triangles;
}

Mesh loadObj(const fs::path& file, const std::string& name) {
    checkObjLines(file, name);
    tinyobj::ObjReaderConfig config;
    // Debian's tinyobjloader (2.0.0rc10, built without mapbox earcut) splits a quad along
    // its shorter diagonal, outside the quad for some concave ones, and its own ear
    // clipping decides convexity from the first edge alone: faces are read whole and
    // triangulated by triangulatePolygon instead.
    config.triangulate = false;
    config.vertex_color = false;
    config.mtl_search_path = file.parent_path().string();
    tinyobj::ObjReader reader;
    if (!reader.ParseFromFile(file.string(), config))
        throw InputError(format("{}: not a readable OBJ file: {}", name, oneLine(reader.Error())));

    const tinyobj::attrib_t& attrib = reader.GetAttrib();
    const std::size_t positionCount = attrib.vertices.size() / 3;
    const std::size_t normalCount = attrib.normals.size() / 3;
    const std::size_t uvCount = attrib.texcoords.size() / 2;

    Mesh mesh;
    mesh.name = file.stem().string();
    bool anyNormal = false, anyUv = false;
    // OBJ indexes positions, normals and UVs separately: each distinct triple becomes one
    // vertex, numbered in order of first use (deterministic).
    std::map<std::array<int, 3>, std::uint32_t> vertexOf;
    std::vector<std::uint32_t> polygon;
    std::vector<glm::dvec3> corners;
    for (const tinyobj::shape_t& shape : reader.GetShapes()) {
        std::size_t offset = 0;
        for (std::size_t f = 0; f < shape.mesh.num_face_vertices.size(); ++f) {
            const std::size_t count = shape.mesh.num_face_vertices[f];
            if (offset + count > shape.mesh.indices.size())
                throw InputError(format("{}: face {} of '{}' runs past the file's indices", name, f + 1, shape.name));
            polygon.clear();
            corners.clear();
            for (std::size_t c = 0; c < count; ++c) {
                const tinyobj::index_t& idx = shape.mesh.indices[offset + c];
                if (idx.vertex_index < 0 || std::size_t(idx.vertex_index) >= positionCount)
                    throw InputError(format("{}: face {} of '{}' uses vertex {} but the file has {} vertices",
                                                 name, f + 1, shape.name, idx.vertex_index + 1, positionCount));
                if (idx.normal_index >= 0 && std::size_t(idx.normal_index) >= normalCount)
                    throw InputError(format("{}: face {} of '{}' uses normal {} but the file has {} normals",
                                                 name, f + 1, shape.name, idx.normal_index + 1, normalCount));
                if (idx.texcoord_index >= 0 && std::size_t(idx.texcoord_index) >= uvCount)
                    throw InputError(format("{}: face {} of '{}' uses UV {} but the file has {} UVs", name,
                                                 f + 1, shape.name, idx.texcoord_index + 1, uvCount));
                const std::array<int, 3> key{idx.vertex_index, idx.normal_index, idx.texcoord_index};
                auto [it, inserted] = vertexOf.try_emplace(key, static_cast<std::uint32_t>(mesh.positions.size()));
                if (inserted) {
                    const float* p = &attrib.vertices[3 * std::size_t(key[0])];
                    mesh.positions.emplace_back(p[0], p[1], p[2]);
                    glm::vec3 n(0.0f);
                    if (key[1] >= 0) {
                        const float* q = &attrib.normals[3 * std::size_t(key[1])];
                        n = {q[0], q[1], q[2]};
                        anyNormal = true;
                    }
                    mesh.normals.push_back(n);
                    glm::vec2 uv(0.0f);
                    if (key[2] >= 0) {
                        const float* q = &attrib.texcoords[2 * std::size_t(key[2])];
                        uv = {q[0], q[1]};
                        anyUv = true;
                    }
                    mesh.uv0.push_back(uv);
                }
                polygon.push_back(it->second);
                corners.emplace_back(mesh.positions[it->second]);
            }
            for (const auto& t : triangulatePolygon(corners))
                mesh.indices.insert(mesh.indices.end(), {polygon[t[0]], polygon[t[1]], polygon[t[2]]});
            offset += count;
        }
    }
    if (!anyNormal) mesh.normals.clear();
    if (!anyUv) mesh.uv0.clear();
    return mesh;
}

// OFF, through CGAL's reader; faces of more than three corners as OBJ's are.
Mesh loadOff(const fs::path& file, const std::string& name) {
    const detail::Polygons soup = detail::readOff(file, name);
    Mesh mesh;
    mesh.name = file.stem().string();
    mesh.positions.reserve(soup.points.size());
    for (const glm::dvec3& p : soup.points) mesh.positions.emplace_back(p);
    std::vector<glm::dvec3> corners;
    for (const std::vector<std::uint32_t>& face : soup.faces) {
        corners.clear();
        for (const std::uint32_t i : face) corners.push_back(soup.points[i]);
        for (const auto& t : triangulatePolygon(corners))
            mesh.indices.insert(mesh.indices.end(), {face[t[0]], face[t[1]], face[t[2]]});
    }
    return mesh;
}

// ---------------------------------------------------------------- glTF

bool skipImage(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int,
               void*) {
    return true;  // geometry only: images are neither decoded nor needed
}

std::string lowerExtension(const fs::path& file) {
    std::string ext = file.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

// tinygltf reads an external image's file before it hands it to skipImage: pictures are said
// not to exist (a warning, not an error), so that a tile does not read its world's textures.
bool fileExistsUnlessPicture(const std::string& file, void* user) {
    const std::string ext = lowerExtension(file);
    for (const char* picture : {".png", ".jpg", ".jpeg", ".webp", ".ktx2"})
        if (ext == picture) return false;
    return tinygltf::FileExists(file, user);
}

int componentCount(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR: return 1;
        case TINYGLTF_TYPE_VEC2: return 2;
        case TINYGLTF_TYPE_VEC3: return 3;
        case TINYGLTF_TYPE_VEC4: return 4;
        default: return 0;
    }
}

int componentSize(int componentType) {
    switch (componentType) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
        case TINYGLTF_COMPONENT_TYPE_SHORT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
        default: return 0;
    }
}

// Reads an accessor as doubles (count × components), checking every bound, with the
// glTF rules for normalized integers.
std::vector<double> readAccessor(const tinygltf::Model& model, int index, const std::string& source,
                                 std::string_view what) {
    if (index < 0 || std::size_t(index) >= model.accessors.size())
        throw InputError(format("{}: {} refers to accessor {} which does not exist", source, what, index));
    const tinygltf::Accessor& a = model.accessors[std::size_t(index)];
    const int components = componentCount(a.type);
    const int size = componentSize(a.componentType);
    if (components == 0 || size == 0)
        throw InputError(format("{}: accessor {} ({}) has an unsupported type", source, index, what));
    if (a.sparse.isSparse)
        throw InputError(format("{}: accessor {} ({}) is sparse, which is not supported", source, index, what));
    constexpr std::size_t kMaxElements = std::size_t(1) << 28;  // no real mesh comes near this
    if (a.count > kMaxElements)
        throw InputError(format("{}: accessor {} ({}) claims {} elements", source, index, what, a.count));
    if (a.bufferView < 0) {  // zeros, per the spec
        // A usable one matches a POSITION accessor stored in the buffers, so it has no more
        // elements than they have bytes; a bigger count would only take memory.
        std::size_t bufferBytes = 0;
        for (const tinygltf::Buffer& b : model.buffers) bufferBytes += b.data.size();
        if (a.count > bufferBytes)
            throw InputError(format("{}: accessor {} ({}) has no data but claims {} elements", source, index, what, a.count));
        return std::vector<double>(a.count * std::size_t(components), 0.0);
    }
    if (std::size_t(a.bufferView) >= model.bufferViews.size())
        throw InputError(format("{}: accessor {} refers to a missing bufferView", source, index));
    const tinygltf::BufferView& view = model.bufferViews[std::size_t(a.bufferView)];
    if (view.buffer < 0 || std::size_t(view.buffer) >= model.buffers.size())
        throw InputError(format("{}: bufferView {} refers to a missing buffer", source, a.bufferView));
    const std::vector<unsigned char>& data = model.buffers[std::size_t(view.buffer)].data;
    const std::size_t element = std::size_t(size) * std::size_t(components);
    const std::size_t stride = view.byteStride ? view.byteStride : element;
    const std::size_t viewEnd = view.byteOffset + view.byteLength;
    if (viewEnd > data.size() || view.byteOffset > data.size())
        throw InputError(format("{}: bufferView {} runs past the end of its buffer", source, a.bufferView));
    if (a.count > 0 && (stride < element || a.byteOffset > view.byteLength ||
                        stride * (a.count - 1) + element > view.byteLength - a.byteOffset))
        throw InputError(format("{}: accessor {} ({}) runs past the end of its bufferView", source, index, what));
    std::vector<double> out(a.count * std::size_t(components), 0.0);
    const unsigned char* base = data.data() + view.byteOffset + a.byteOffset;
    for (std::size_t i = 0; i < a.count; ++i) {
        const unsigned char* e = base + i * stride;
        for (int c = 0; c < components; ++c) {
            const unsigned char* p = e + std::size_t(c) * std::size_t(size);
            double v = 0.0;
            switch (a.componentType) {
                case TINYGLTF_COMPONENT_TYPE_FLOAT: { float f; std::memcpy(&f, p, 4); v = f; break; }
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: { std::uint32_t u; std::memcpy(&u, p, 4); v = u; break; }
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
                    std::uint16_t u; std::memcpy(&u, p, 2);
                    v = a.normalized ? u / 65535.0 : u; break;
                }
                case TINYGLTF_COMPONENT_TYPE_SHORT: {
                    std::int16_t s; std::memcpy(&s, p, 2);
                    v = a.normalized ? std::max(s / 32767.0, -1.0) : s; break;
                }
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: v = a.normalized ? *p / 255.0 : *p; break;
                case TINYGLTF_COMPONENT_TYPE_BYTE: {
                    const auto s = static_cast<std::int8_t>(*p);
                    v = a.normalized ? std::max(s / 127.0, -1.0) : s; break;
                }
            }
            out[i * std::size_t(components) + std::size_t(c)] = v;
        }
    }
    return out;
}

int accessorComponents(const tinygltf::Model& model, int index) {
    return componentCount(model.accessors[std::size_t(index)].type);
}

std::vector<std::uint32_t> readTriangles(const tinygltf::Model& model, const tinygltf::Primitive& prim, std::size_t n,
                                         const std::string& source);

Mesh readPrimitive(const tinygltf::Model& model, const tinygltf::Primitive& prim, const std::string& source) {
    Mesh mesh;
    const auto position = prim.attributes.find("POSITION");
    if (position == prim.attributes.end()) return mesh;
    const std::vector<double> p = readAccessor(model, position->second, source, "POSITION");
    if (accessorComponents(model, position->second) != 3)
        throw InputError(format("{}: POSITION must have three components", source));
    const std::size_t n = p.size() / 3;
    for (std::size_t i = 0; i < n; ++i)
        mesh.positions.emplace_back(float(p[3 * i]), float(p[3 * i + 1]), float(p[3 * i + 2]));

    auto vecAttribute = [&](const char* semantic, int wanted) -> std::vector<double> {
        const auto it = prim.attributes.find(semantic);
        if (it == prim.attributes.end()) return {};
        std::vector<double> v = readAccessor(model, it->second, source, semantic);
        const int c = accessorComponents(model, it->second);
        if ((wanted > 0 && c != wanted) || v.size() / std::size_t(c) != n)
            throw InputError(format("{}: attribute {} does not match POSITION", source, semantic));
        return v;
    };
    if (auto v = vecAttribute("NORMAL", 3); !v.empty())
        for (std::size_t i = 0; i < n; ++i) mesh.normals.emplace_back(float(v[3 * i]), float(v[3 * i + 1]), float(v[3 * i + 2]));
    if (auto v = vecAttribute("TEXCOORD_0", 2); !v.empty())
        for (std::size_t i = 0; i < n; ++i) mesh.uv0.emplace_back(float(v[2 * i]), float(v[2 * i + 1]));
    if (auto v = vecAttribute("TEXCOORD_1", 2); !v.empty())
        for (std::size_t i = 0; i < n; ++i) mesh.uv1.emplace_back(float(v[2 * i]), float(v[2 * i + 1]));
    if (auto v = vecAttribute("TEXCOORD_2", 2); !v.empty())
        for (std::size_t i = 0; i < n; ++i) mesh.uv2.emplace_back(float(v[2 * i]), float(v[2 * i + 1]));
    if (auto v = vecAttribute("TEXCOORD_3", 2); !v.empty())
        for (std::size_t i = 0; i < n; ++i) mesh.uv3.emplace_back(float(v[2 * i]), float(v[2 * i + 1]));
    if (auto v = vecAttribute("_MATERIAL_ID", 1); !v.empty()) {
        for (double x : v) {
            if (!(x >= 0.0 && x < kMaterialIdCount) || x != std::floor(x))
                throw InputError(format("{}: a _MATERIAL_ID ({}) is not a material ID (0..15)", source, x));
            mesh.materialIds.push_back(static_cast<std::uint8_t>(x));
        }
    } else if (auto c0 = vecAttribute("COLOR_0", 0); !c0.empty()) {
        // Files written before _MATERIAL_ID carried the material ID in COLOR_0 as binary RGBA: read
        // only when it is binary (every channel 0 or 1).
        const std::vector<double>& v = c0;
        const std::size_t c = v.size() / n;
        if (c != 3 && c != 4) throw InputError(format("{}: COLOR_0 must have three or four components", source));
        if (std::all_of(v.begin(), v.end(), [](double x) { return x == 0.0 || x == 1.0; }))
            for (std::size_t i = 0; i < n; ++i)
                mesh.materialIds.push_back(colorToMaterialId(
                    glm::vec4(float(v[c * i]), float(v[c * i + 1]), float(v[c * i + 2]), c == 4 ? float(v[c * i + 3]) : 0.0f)));
    }
    if (auto v = vecAttribute("_PIECE_ID", 1); !v.empty())
        for (double x : v) {
            if (std::isnan(x)) throw InputError(format("{}: a _PIECE_ID is not a number", source));
            mesh.pieceIds.push_back(static_cast<std::uint32_t>(std::clamp(x, 0.0, 4294967295.0)));
        }

    mesh.indices = readTriangles(model, prim, n, source);
    return mesh;
}

// A primitive's triangles (strips and fans turned into lists; points and lines: none), checked
// against its `n` vertices.
std::vector<std::uint32_t> readTriangles(const tinygltf::Model& model, const tinygltf::Primitive& prim, std::size_t n,
                                         const std::string& source) {
    std::vector<std::uint32_t> order, triangles;
    if (prim.indices >= 0) {
        for (double x : readAccessor(model, prim.indices, source, "indices")) {
            if (!(x >= 0.0 && x < double(n)))  // also NaN and negative (float or signed accessors)
                throw InputError(format("{}: an index ({}) is out of range for {} vertices", source, x, n));
            order.push_back(static_cast<std::uint32_t>(x));
        }
    } else {
        for (std::size_t i = 0; i < n; ++i) order.push_back(static_cast<std::uint32_t>(i));
    }
    const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
    if (mode == TINYGLTF_MODE_TRIANGLES) {
        order.resize(order.size() - order.size() % 3);
        return order;
    }
    if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
        for (std::size_t i = 2; i < order.size(); ++i) {
            const bool even = i % 2 == 0;
            triangles.insert(triangles.end(), {order[i - 2], even ? order[i - 1] : order[i], even ? order[i] : order[i - 1]});
        }
    } else if (mode == TINYGLTF_MODE_TRIANGLE_FAN) {
        for (std::size_t i = 2; i < order.size(); ++i) triangles.insert(triangles.end(), {order[0], order[i - 1], order[i]});
    }  // points and lines are not surfaces: skipped
    return triangles;
}

// Our own files' triangle order (gltf.hpp): extras.triangle_primitive names, triangle by
// triangle, the primitive that holds it; `mesh` holds the primitives' triangles one after the
// other, `counts` how many each. Files without it, or whose extras no longer match their
// primitives (another tool edited them), keep the primitives' order: the mesh is whole either way.
void restoreTriangleOrder(const tinygltf::Model& model, const tinygltf::Mesh& gltfMesh, const std::vector<std::size_t>& counts,
                          Mesh& mesh, const std::string& source) {
    if (!gltfMesh.extras.IsObject() || !gltfMesh.extras.Has("triangle_primitive") || counts.size() < 2) return;
    const tinygltf::Value& index = gltfMesh.extras.Get("triangle_primitive");
    if (!index.IsInt() || index.Get<int>() < 0 || std::size_t(index.Get<int>()) >= model.accessors.size()) return;
    const std::vector<double> owner = readAccessor(model, index.Get<int>(), source, "triangle_primitive");
    std::vector<std::size_t> next(counts.size(), 0), left = counts;
    for (std::size_t k = 1; k < counts.size(); ++k) next[k] = next[k - 1] + counts[k - 1];
    if (owner.size() != mesh.triangleCount()) return;
    std::vector<std::uint32_t> ordered;
    ordered.reserve(mesh.indices.size());
    for (double x : owner) {
        const auto k = std::size_t(x);
        if (!(x >= 0.0 && k < counts.size()) || left[k] == 0) return;
        --left[k];
        const std::size_t t = next[k]++;
        ordered.insert(ordered.end(), mesh.indices.begin() + std::ptrdiff_t(3 * t), mesh.indices.begin() + std::ptrdiff_t(3 * t + 3));
    }
    mesh.indices = std::move(ordered);
}

// A glTF mesh as one Mesh. Primitives that share their vertex accessors with the one before
// (ours: one primitive per material) add only their triangles; others add their vertices too.
Mesh readMesh(const tinygltf::Model& model, const tinygltf::Mesh& gltfMesh, const std::string& source) {
    Mesh mesh;
    mesh.name = gltfMesh.name;
    std::vector<std::size_t> counts;  // triangles per primitive, while they all share one vertex set
    bool sharing = true;
    const std::map<std::string, int>* shared = nullptr;
    std::size_t base = 0;
    for (const tinygltf::Primitive& prim : gltfMesh.primitives) {
        const std::size_t before = mesh.triangleCount();
        if (shared && prim.attributes == *shared) {
            const std::size_t n = mesh.positions.size() - base;
            for (std::uint32_t i : readTriangles(model, prim, n, source)) mesh.indices.push_back(std::uint32_t(base + i));
        } else {
            Mesh part = readPrimitive(model, prim, source);
            if (part.positions.empty()) continue;
            sharing = !shared;
            base = mesh.positions.size();
            shared = &prim.attributes;
            appendMesh(mesh, part, glm::mat4(1.0f));
        }
        counts.push_back(mesh.triangleCount() - before);
    }
    if (sharing) restoreTriangleOrder(model, gltfMesh, counts, mesh, source);
    return mesh;
}

glm::mat4 localMatrix(const tinygltf::Node& node) {
    if (node.matrix.size() == 16) {
        glm::dmat4 m = glm::make_mat4(node.matrix.data());
        return glm::mat4(m);
    }
    glm::dmat4 m(1.0);
    if (node.translation.size() == 3)
        m = glm::translate(m, glm::dvec3(node.translation[0], node.translation[1], node.translation[2]));
    if (node.rotation.size() == 4)
        m *= glm::mat4_cast(glm::dquat(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]));
    if (node.scale.size() == 3) m = glm::scale(m, glm::dvec3(node.scale[0], node.scale[1], node.scale[2]));
    return glm::mat4(m);
}

void addNode(const tinygltf::Model& model, int index, const glm::mat4& parent, int parentEntry,
             std::vector<MeshNode>& out, std::vector<bool>& visited, const std::string& source) {
    if (index < 0 || std::size_t(index) >= model.nodes.size())
        throw InputError(format("{}: node {} does not exist", source, index));
    if (visited[std::size_t(index)])
        throw InputError(format("{}: node {} appears twice in the hierarchy (a cycle?)", source, index));
    visited[std::size_t(index)] = true;
    const tinygltf::Node& node = model.nodes[std::size_t(index)];
    const glm::mat4 world = parent * localMatrix(node);
    if (node.mesh >= 0) {
        if (std::size_t(node.mesh) >= model.meshes.size())
            throw InputError(format("{}: node {} refers to mesh {} which does not exist", source, index, node.mesh));
        MeshNode entry;
        entry.name = node.name;
        entry.world = world;
        entry.parent = parentEntry;
        entry.mesh = readMesh(model, model.meshes[std::size_t(node.mesh)], source);
        parentEntry = int(out.size());
        out.push_back(std::move(entry));
    }
    for (int child : node.children) addNode(model, child, world, parentEntry, out, visited, source);
}

// The JSON of a .gltf file, or of a GLB's first chunk (read alone: a GLB may be a
// gigabyte); empty if there is none to read (tinygltf then says what is wrong). A GLB of
// version 1 is KHR_binary_glTF, glTF 1.0.
std::string gltfJson(const fs::path& file, const std::string& name) {
    std::ifstream in(file, std::ios::binary);
    std::array<std::uint32_t, 5> header{};  // magic, version, length, chunk length, chunk type
    in.read(reinterpret_cast<char*>(header.data()), sizeof header);
    const auto got = static_cast<std::size_t>(in.gcount());
    if (got < 4 || std::memcmp(header.data(), "glTF", 4) != 0) {
        in.clear();
        in.seekg(0);
        return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    }
    if (got >= 8 && header[1] == 1)
        throw InputError(format("{}: glTF 1.0 is not supported (re-export as glTF 2.0)", name));
    std::error_code ec;
    const std::uintmax_t size = fs::file_size(file, ec);
    if (got < sizeof header || header[4] != 0x4E4F534Au || ec || header[3] > size - sizeof header) return {};
    std::string json(header[3], '\0');
    in.read(json.data(), std::streamsize(json.size()));
    return in ? json : std::string();
}

// Refuses by name what tinygltf would misread: glTF 1.0 (objects keyed by ID where 2.0
// has arrays) and Draco-compressed primitives, whose accessors have no data of their own.
// A file that only uses Draco, with an uncompressed fallback in every accessor, is read.
void checkGltfFlavour(const fs::path& file, const std::string& name) {
    const nlohmann::json doc = nlohmann::json::parse(gltfJson(file, name), nullptr, false);
    if (!doc.is_object()) return;
    bool version1 = false;
    if (const auto asset = doc.find("asset"); asset != doc.end() && asset->is_object()) {
        if (const auto v = asset->find("version"); v != asset->end()) {
            if (v->is_string()) version1 = v->get<std::string>().starts_with("1");
            else if (v->is_number()) version1 = v->get<double>() >= 1.0 && v->get<double>() < 2.0;
        }
    }
    for (const char* key : {"meshes", "accessors", "nodes"})
        if (const auto it = doc.find(key); it != doc.end() && it->is_object()) version1 = true;
    if (version1) throw InputError(format("{}: glTF 1.0 is not supported (re-export as glTF 2.0)", name));

    constexpr const char* kDraco = "KHR_draco_mesh_compression";
    auto lists = [&](const char* key) {
        const auto it = doc.find(key);
        return it != doc.end() && it->is_array() && std::find(it->begin(), it->end(), kDraco) != it->end();
    };
    const std::string refusal =
        format("{}: Draco-compressed meshes are not supported (export without Draco compression)", name);
    if (lists("extensionsRequired")) throw InputError(refusal);
    if (!lists("extensionsUsed")) return;
    const auto accessors = doc.find("accessors");
    auto hasData = [&](const nlohmann::json& index) {
        if (!index.is_number_unsigned() || accessors == doc.end() || !accessors->is_array()) return false;
        const std::size_t i = index.get<std::size_t>();
        return i < accessors->size() && (*accessors)[i].is_object() && (*accessors)[i].contains("bufferView");
    };
    const auto meshes = doc.find("meshes");
    if (meshes == doc.end() || !meshes->is_array()) return;
    for (const nlohmann::json& mesh : *meshes) {
        if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
        for (const nlohmann::json& prim : mesh["primitives"]) {
            if (!prim.is_object() || !prim.contains("extensions") || !prim["extensions"].is_object() ||
                !prim["extensions"].contains(kDraco))
                continue;
            if (prim.contains("indices") && !hasData(prim["indices"])) throw InputError(refusal);
            if (prim.contains("attributes") && prim["attributes"].is_object())
                for (const nlohmann::json& attribute : prim["attributes"])
                    if (!hasData(attribute)) throw InputError(refusal);
        }
    }
}

std::vector<MeshNode> loadGltfNodes(const fs::path& file, const std::string& name) {
    checkGltfFlavour(file, name);
    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(skipImage, nullptr);
    loader.SetFsCallbacks({fileExistsUnlessPicture, tinygltf::ExpandFilePath, tinygltf::ReadWholeFile,
                           tinygltf::WriteWholeFile, nullptr});
    tinygltf::Model model;
    std::string err, warn;
    char magic[4] = {};
    std::ifstream(file, std::ios::binary).read(magic, 4);
    const bool binary = std::memcmp(magic, "glTF", 4) == 0;
    const bool ok = binary ? loader.LoadBinaryFromFile(&model, &err, &warn, file.string())
                           : loader.LoadASCIIFromFile(&model, &err, &warn, file.string());
    if (!ok) throw InputError(format("{}: not a readable glTF file: {}", name, oneLine(err)));

    std::vector<MeshNode> nodes;
    std::vector<bool> visited(model.nodes.size(), false);
    std::vector<int> roots;
    if (!model.scenes.empty()) {
        const std::size_t s = model.defaultScene >= 0 ? std::size_t(model.defaultScene) : 0;
        if (s >= model.scenes.size()) throw InputError(format("{}: the default scene does not exist", name));
        roots = model.scenes[s].nodes;
    } else {  // no scene: every node that is nobody's child
        std::vector<bool> isChild(model.nodes.size(), false);
        for (const tinygltf::Node& node : model.nodes)
            for (int c : node.children)
                if (c >= 0 && std::size_t(c) < isChild.size()) isChild[std::size_t(c)] = true;
        for (std::size_t i = 0; i < model.nodes.size(); ++i)
            if (!isChild[i]) roots.push_back(int(i));
    }
    for (int root : roots) addNode(model, root, glm::mat4(1.0f), -1, nodes, visited, name);
    return nodes;
}

void checkReadable(const fs::path& file, const std::string& name) {
    std::error_code ec;
    if (!fs::exists(file, ec)) throw InputError(format("{}: no such file", name));
    if (fs::is_directory(file, ec)) throw InputError(format("{}: is a folder, not a mesh file", name));
    if (fs::file_size(file, ec) == 0 || ec) throw InputError(format("{}: the file is empty", name));
    if (!std::ifstream(file)) throw InputError(format("{}: cannot be read", name));
}

// The nodes of any format but OBJ: glTF through tinygltf, the rest through Assimp.
std::vector<MeshNode> loadNodes(const fs::path& file, const std::string& name, const std::string& ext) {
    if (ext == ".gltf" || ext == ".glb") return loadGltfNodes(file, name);
    if (detail::assimpReadsExtension(ext)) return detail::loadAssimpNodes(file, name);
    throw InputError(format("{}: unknown mesh format '{}' (expected .obj, .gltf, .glb, .fbx, .dae, .stl, .ply, .off, "
                            ".3ds or another format Assimp reads)",
                            name, ext));
}

// The formats read as one mesh, without nodes: OBJ and OFF; nothing for the others.
std::optional<Mesh> loadWholeMesh(const fs::path& file, const std::string& name, const std::string& ext) {
    if (ext == ".obj") return loadObj(file, name);
    if (ext == ".off") return loadOff(file, name);
    return std::nullopt;
}

// What a reader is called in messages: "the FBX reader".
std::string readerName(const std::string& ext) {
    if (ext == ".gltf" || ext == ".glb") return "glTF";
    std::string upper = ext.substr(1);
    std::transform(upper.begin(), upper.end(), upper.begin(), [](unsigned char c) { return char(std::toupper(c)); });
    return upper;
}

bool isWholeFormat(const std::string& ext) { return ext == ".obj" || ext == ".off"; }

// The nodes of a file, read in this process: a whole-mesh format as one node named after the file.
std::vector<MeshNode> readNodes(const fs::path& file, const std::string& name, const std::string& ext) {
    std::optional<Mesh> whole = loadWholeMesh(file, name, ext);
    if (!whole) return loadNodes(file, name, ext);
    std::vector<MeshNode> nodes(1);
    nodes[0].name = file.stem().string();
    nodes[0].mesh = std::move(*whole);
    return nodes;
}

// readNodes where `where` says, after the checks that need no reader.
std::vector<MeshNode> readNodesIn(ReadIn where, const fs::path& file, const std::string& name) {
    checkReadable(file, name);
    const std::string ext = lowerExtension(file);
    if (where == ReadIn::thisProcess) return readNodes(file, name, ext);
    if (!isWholeFormat(ext) && ext != ".gltf" && ext != ".glb" && !detail::assimpReadsExtension(ext))
        return loadNodes(file, name, ext);  // refuses the extension by name, without a child
    std::vector<MeshNode> nodes;
    readIsolated(
        file, readerName(ext),
        [&] { return detail::encodeNodes(std::make_shared<const std::vector<MeshNode>>(readNodes(file, name, ext))); },
        [&](AnswerSource& answer) { nodes = detail::decodeNodes(answer, name); });
    if (isWholeFormat(ext) && nodes.size() != 1)
        throw InputError(format("{}: the reader's answer is damaged ({} nodes for one mesh)", name, nodes.size()));
    return nodes;
}

}  // namespace

Mesh loadMesh(const fs::path& file, ReadIn where) {
    const std::string name = file.string();
    std::vector<MeshNode> nodes = readNodesIn(where, file, name);
    Mesh mesh;
    if (isWholeFormat(lowerExtension(file))) {
        mesh = std::move(nodes.front().mesh);
    } else {
        mesh.name = file.stem().string();
        for (const MeshNode& node : nodes) appendMesh(mesh, node.mesh, node.world);
    }
    validateMeshData(mesh, name);
    return mesh;
}

std::vector<MeshNode> loadMeshNodes(const fs::path& file, ReadIn where) {
    const std::string name = file.string();
    std::vector<MeshNode> nodes = readNodesIn(where, file, name);
    for (const MeshNode& node : nodes) validateMeshData(node.mesh, format("{} (node '{}')", name, node.name));
    return nodes;
}

}  // namespace dawnforge
