// Level-set meshing with OpenVDB 10: tools::meshToLevelSet for the input's signed
// distance, tools::volumeToMesh for each piece. Value noise: lattice values hashed from
// the seed, smoothstep-interpolated, two octaves.
#include "rough.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/seed.hpp>

#include <glm/geometric.hpp>
#include <openvdb/openvdb.h>
#include <openvdb/tools/LevelSetUtil.h>
#include <openvdb/tools/MeshToVolume.h>
#include <openvdb/tools/VolumeToMesh.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <mutex>
#include <numeric>
#include <optional>
#include <span>

namespace dawnforge::sim::detail {

namespace {

double lattice(std::uint64_t seed, std::int64_t x, std::int64_t y, std::int64_t z) {
    const std::uint64_t h = mix64(seed ^ mix64(std::uint64_t(x) * 0x9e3779b97f4a7c15ull ^
                                               mix64(std::uint64_t(y) * 0xc2b2ae3d27d4eb4full ^ std::uint64_t(z))));
    return double(h >> 11) * 0x1.0p-52 - 1.0;  // [-1, 1)
}

double valueNoise(std::uint64_t seed, const glm::dvec3& p) {
    const glm::dvec3 f = glm::floor(p);
    const glm::dvec3 t = p - f;
    const glm::dvec3 s = t * t * (3.0 - 2.0 * t);
    const auto x = std::int64_t(f.x), y = std::int64_t(f.y), z = std::int64_t(f.z);
    double v = 0.0;
    for (int c = 0; c < 8; ++c) {
        const int dx = c & 1, dy = (c >> 1) & 1, dz = (c >> 2) & 1;
        const double w = (dx ? s.x : 1 - s.x) * (dy ? s.y : 1 - s.y) * (dz ? s.z : 1 - s.z);
        v += w * lattice(seed, x + dx, y + dy, z + dz);
    }
    return v;
}

double noise(std::uint64_t seed, double featureSize, const glm::dvec3& p) {
    const glm::dvec3 q = p / featureSize;
    return (valueNoise(seed, q) + 0.5 * valueNoise(seed + 1, 2.0 * q)) / 1.5;
}

struct Field {
    const RoughCell& cell;
    const RoughSettings& s;
    // The largest plane term and which plane gave it.
    double planes(const glm::dvec3& p, std::size_t* which = nullptr) const {
        const double n = noise(s.seed, s.featureSize, p) * s.amplitude;
        double best = -std::numeric_limits<double>::max();
        for (std::size_t k = 0; k < cell.planes.size(); ++k) {
            const RoughPlane& pl = cell.planes[k];
            const double g = glm::dot(pl.normal, p) + pl.offset + pl.noiseSign * n;
            if (g > best) {
                best = g;
                if (which) *which = k;
            }
        }
        return best;
    }
};

std::uint8_t mostCommonMaterial(const Mesh& m) {
    std::array<std::size_t, kMaterialIdCount> count{};
    for (std::uint8_t id : m.materialIds) ++count[id];
    return m.materialIds.empty() ? 0 : std::uint8_t(std::max_element(count.begin(), count.end()) - count.begin());
}

// What every cell's meshing shares: the input's signed distance on the voxel lattice.
struct Lattice {
    double voxel = 0.0;                     // m
    openvdb::math::Transform::Ptr xform;
    openvdb::FloatGrid::Ptr meshSdf;
    openvdb::CoordBBox meshBox;             // the active voxels of meshSdf
    double band = 0.0;                      // narrow-band half width (m)
    std::uint8_t surfaceMaterial = 0;       // of faces on the input's surface
};

Lattice inputLattice(const Mesh& input, const RoughSettings& s) {
    constexpr float kHalfWidth = 3.0f;  // voxels
    Lattice lattice;
    lattice.voxel = s.voxelSize;
    lattice.xform = openvdb::math::Transform::createLinearTransform(lattice.voxel);
    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec3I> triangles;
    for (const glm::vec3& p : input.positions) points.emplace_back(p.x, p.y, p.z);
    for (std::size_t t = 0; t < input.triangleCount(); ++t)
        triangles.emplace_back(input.indices[3 * t], input.indices[3 * t + 1], input.indices[3 * t + 2]);
    lattice.meshSdf = openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*lattice.xform, points, triangles, kHalfWidth);
    lattice.meshBox = lattice.meshSdf->evalActiveVoxelBoundingBox();
    lattice.band = kHalfWidth * lattice.voxel;
    lattice.surfaceMaterial = mostCommonMaterial(input);
    return lattice;
}

// The voxels that can hold a cell's piece: its exact bounds grown by the noise and two
// voxels, clipped to the input's; none when the cell misses the input.
std::optional<openvdb::CoordBBox> cellBox(const RoughCell& cell, const RoughSettings& s, const Lattice& lattice) {
    const double v = lattice.voxel;
    const double margin = s.amplitude + 2.0 * v;
    openvdb::Coord lo(int(std::floor((cell.lo.x - margin) / v)), int(std::floor((cell.lo.y - margin) / v)),
                      int(std::floor((cell.lo.z - margin) / v)));
    openvdb::Coord hi(int(std::ceil((cell.hi.x + margin) / v)), int(std::ceil((cell.hi.y + margin) / v)),
                      int(std::ceil((cell.hi.z + margin) / v)));
    lo = openvdb::Coord::maxComponent(lo, lattice.meshBox.min().offsetBy(-2));
    hi = openvdb::Coord::minComponent(hi, lattice.meshBox.max().offsetBy(2));
    if (lo.x() > hi.x() || lo.y() > hi.y() || lo.z() > hi.z()) return std::nullopt;
    return openvdb::CoordBBox(lo, hi);
}

// The piece's level set, max(input SDF, plane terms), sampled over `box`; null when no
// voxel is inside.
openvdb::FloatGrid::Ptr cellLevelSet(const Lattice& lattice, const Field& field, const openvdb::CoordBBox& box,
                                     const openvdb::FloatGrid::ConstAccessor& meshAccessor) {
    const double band = lattice.band;
    const openvdb::Coord lo = box.min(), hi = box.max();
    openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(float(band));
    grid->setTransform(lattice.xform);
    grid->setGridClass(openvdb::GRID_LEVEL_SET);
    auto acc = grid->getAccessor();
    bool any = false;
    for (int i = lo.x(); i <= hi.x(); ++i)
        for (int j = lo.y(); j <= hi.y(); ++j)
            for (int k = lo.z(); k <= hi.z(); ++k) {
                const openvdb::Coord ijk(i, j, k);
                // Outside the box the piece is empty: the box faces close it.
                const bool border = i == lo.x() || i == hi.x() || j == lo.y() || j == hi.y() || k == lo.z() || k == hi.z();
                const double phi = border ? band
                                          : std::max(double(meshAccessor.getValue(ijk)),
                                                     field.planes(glm::dvec3(i, j, k) * lattice.voxel));
                if (std::abs(phi) < band) {
                    acc.setValue(ijk, float(phi));
                    any |= phi < 0.0;
                } else if (phi < 0.0) {
                    acc.setValueOff(ijk, -float(band));
                    any = true;
                }
            }
    if (!any) return nullptr;
    openvdb::tools::signedFloodFill(grid->tree());
    return grid;
}

struct Triangles {
    std::vector<glm::dvec3> positions;
    std::vector<std::array<std::uint32_t, 3>> corners;
};

// The zero level set as triangles (quads split along a fixed diagonal), made
// counter-clockwise outward.
Triangles zeroSurface(const openvdb::FloatGrid& grid) {
    std::vector<openvdb::Vec3s> vp;
    std::vector<openvdb::Vec3I> vt;
    std::vector<openvdb::Vec4I> vq;
    openvdb::tools::volumeToMesh(grid, vp, vt, vq, 0.0, 0.0);
    Triangles out;
    if (vp.empty()) return out;
    for (const auto& t : vt) out.corners.push_back({t[0], t[1], t[2]});
    for (const auto& q : vq) {
        out.corners.push_back({q[0], q[1], q[2]});
        out.corners.push_back({q[0], q[2], q[3]});
    }
    out.positions.resize(vp.size());
    for (std::size_t i = 0; i < vp.size(); ++i) out.positions[i] = {vp[i][0], vp[i][1], vp[i][2]};
    const std::vector<glm::dvec3>& pos = out.positions;
    double signedVolume = 0.0;
    for (const auto& t : out.corners) signedVolume += glm::dot(pos[t[0]], glm::cross(pos[t[1]], pos[t[2]]));
    if (signedVolume < 0.0)
        for (auto& t : out.corners) std::swap(t[1], t[2]);
    return out;
}

// Islands: the triangles connected through shared vertices, keyed by their smallest
// vertex (so in a fixed order).
std::map<std::uint32_t, std::vector<std::size_t>> islands(const Triangles& tris) {
    std::vector<std::uint32_t> parent(tris.positions.size());
    std::iota(parent.begin(), parent.end(), 0u);
    auto find = [&](std::uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    for (const auto& t : tris.corners)
        for (int e = 1; e < 3; ++e) {
            const std::uint32_t a = find(t[0]), b = find(t[std::size_t(e)]);
            if (a != b) parent[std::max(a, b)] = std::min(a, b);
        }
    std::map<std::uint32_t, std::vector<std::size_t>> out;
    for (std::size_t t = 0; t < tris.corners.size(); ++t) out[find(tris.corners[t][0])].push_back(t);
    return out;
}

// Area-weighted vertex normals of an island's triangles (zero off the island).
std::vector<glm::dvec3> vertexNormals(const Triangles& tris, std::span<const std::size_t> members) {
    const std::vector<glm::dvec3>& pos = tris.positions;
    std::vector<glm::dvec3> normals(pos.size(), glm::dvec3(0.0));
    for (std::size_t t : members) {
        const auto& tri = tris.corners[t];
        const glm::dvec3 n = glm::cross(pos[tri[1]] - pos[tri[0]], pos[tri[2]] - pos[tri[0]]);
        for (std::uint32_t i : tri) normals[i] += n;
    }
    return normals;
}

// Planar UVs in metres on the plane the normal faces most.
glm::dvec2 planarUv(const glm::dvec3& p, const glm::dvec3& n) {
    const glm::dvec3 a = glm::abs(n);
    return a.x >= a.y && a.x >= a.z ? glm::dvec2(p.z, p.y) : a.y >= a.z ? glm::dvec2(p.x, p.z) : glm::dvec2(p.x, p.y);
}

// What a triangle lies on: a cut where a plane term bounds the piece (the neighbour
// cell across it, the interior material), else the input's surface (-1, its material).
struct Face {
    std::int64_t key = -1;
    std::uint8_t material = 0;
};

Face faceAt(const glm::dvec3& centroid, const Field& field, const Lattice& lattice,
            const openvdb::FloatGrid::ConstAccessor& meshAccessor) {
    const openvdb::Vec3d ijk = lattice.xform->worldToIndex(openvdb::Vec3d(centroid.x, centroid.y, centroid.z));
    const double meshPhi = meshAccessor.getValue(openvdb::Coord::round(ijk));
    std::size_t which = 0;
    const double planePhi = field.planes(centroid, &which);
    if (planePhi > meshPhi) return {field.cell.planes[which].neighbour, field.s.interiorMaterial};
    return {-1, lattice.surfaceMaterial};
}

// One island as a piece. A vertex is written again when a triangle of another material
// uses it, so cut and surface faces share no vertex (each keeps its own normal and UVs).
RoughPiece islandPiece(const Triangles& tris, std::span<const std::size_t> members, const Field& field,
                       const Lattice& lattice, const openvdb::FloatGrid::ConstAccessor& meshAccessor) {
    const std::vector<glm::dvec3>& pos = tris.positions;
    const std::vector<glm::dvec3> normals = vertexNormals(tris, members);
    RoughPiece piece;
    Mesh& mesh = piece.mesh;
    std::vector<std::uint32_t> index(pos.size(), UINT32_MAX);
    for (std::size_t t : members) {
        const auto& tri = tris.corners[t];
        const glm::dvec3 centroid = (pos[tri[0]] + pos[tri[1]] + pos[tri[2]]) / 3.0;
        const Face face = faceAt(centroid, field, lattice, meshAccessor);
        piece.triangleKeys.push_back(face.key);
        for (std::uint32_t i : tri) {
            if (index[i] == UINT32_MAX || mesh.materialIds[index[i]] != face.material) {
                index[i] = std::uint32_t(mesh.positions.size());
                const glm::dvec3 n = glm::length(normals[i]) > 0 ? glm::normalize(normals[i]) : glm::dvec3(0, 1, 0);
                mesh.positions.push_back(glm::vec3(pos[i]));
                mesh.normals.push_back(glm::vec3(n));
                mesh.uv0.push_back(glm::vec2(planarUv(pos[i], n) / field.s.uvScale));
                mesh.materialIds.push_back(face.material);
            }
            mesh.indices.push_back(index[i]);
        }
    }
    return piece;
}

std::vector<RoughPiece> cellPieces(const RoughCell& cell, const RoughSettings& s, const Lattice& lattice) {
    const Field field{cell, s};
    const auto meshAccessor = lattice.meshSdf->getConstAccessor();
    const std::optional<openvdb::CoordBBox> box = cellBox(cell, s, lattice);
    if (!box) return {};
    const openvdb::FloatGrid::Ptr grid = cellLevelSet(lattice, field, *box, meshAccessor);
    if (!grid) return {};
    const Triangles tris = zeroSurface(*grid);
    if (tris.positions.empty()) return {};
    std::vector<RoughPiece> pieces;
    for (const auto& [root, members] : islands(tris)) pieces.push_back(islandPiece(tris, members, field, lattice, meshAccessor));
    return pieces;
}

}  // namespace

std::vector<std::vector<RoughPiece>> roughPieces(const Mesh& input, const std::vector<RoughCell>& cells,
                                                 const RoughSettings& s) {
    static std::once_flag once;
    std::call_once(once, [] { openvdb::initialize(); });
    const Lattice lattice = inputLattice(input, s);
    std::vector<std::vector<RoughPiece>> out(cells.size());
    tbb::parallel_for(std::size_t(0), cells.size(), [&](std::size_t c) { out[c] = cellPieces(cells[c], s, lattice); });
    return out;
}

}  // namespace dawnforge::sim::detail
