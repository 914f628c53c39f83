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

}  // namespace

std::vector<std::vector<RoughPiece>> roughPieces(const Mesh& input, const std::vector<RoughCell>& cells,
                                                 const RoughSettings& s) {
    static std::once_flag once;
    std::call_once(once, [] { openvdb::initialize(); });
    const double v = s.voxelSize;
    const auto xform = openvdb::math::Transform::createLinearTransform(v);
    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec3I> triangles;
    for (const glm::vec3& p : input.positions) points.emplace_back(p.x, p.y, p.z);
    for (std::size_t t = 0; t < input.triangleCount(); ++t)
        triangles.emplace_back(input.indices[3 * t], input.indices[3 * t + 1], input.indices[3 * t + 2]);
    const float halfWidth = 3.0f;
    const openvdb::FloatGrid::Ptr meshSdf = openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*xform, points, triangles, halfWidth);
    const std::uint8_t surfaceMaterial = mostCommonMaterial(input);
    const double band = halfWidth * v;

    std::vector<std::vector<RoughPiece>> out(cells.size());
    tbb::parallel_for(std::size_t(0), cells.size(), [&](std::size_t c) {
        const Field field{cells[c], s};
        auto meshAccessor = meshSdf->getConstAccessor();
        const openvdb::CoordBBox meshBox = meshSdf->evalActiveVoxelBoundingBox();
        const double margin = s.amplitude + 2.0 * v;
        openvdb::Coord lo(int(std::floor((cells[c].lo.x - margin) / v)), int(std::floor((cells[c].lo.y - margin) / v)),
                          int(std::floor((cells[c].lo.z - margin) / v)));
        openvdb::Coord hi(int(std::ceil((cells[c].hi.x + margin) / v)), int(std::ceil((cells[c].hi.y + margin) / v)),
                          int(std::ceil((cells[c].hi.z + margin) / v)));
        lo = openvdb::Coord::maxComponent(lo, meshBox.min().offsetBy(-2));
        hi = openvdb::Coord::minComponent(hi, meshBox.max().offsetBy(2));
        if (lo.x() > hi.x() || lo.y() > hi.y() || lo.z() > hi.z()) return;

        openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(float(band));
        grid->setTransform(xform);
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
                                              : std::max(double(meshAccessor.getValue(ijk)), field.planes(glm::dvec3(i, j, k) * v));
                    if (std::abs(phi) < band) {
                        acc.setValue(ijk, float(phi));
                        any |= phi < 0.0;
                    } else if (phi < 0.0) {
                        acc.setValueOff(ijk, -float(band));
                        any = true;
                    }
                }
        if (!any) return;
        openvdb::tools::signedFloodFill(grid->tree());
        std::vector<openvdb::Vec3s> vp;
        std::vector<openvdb::Vec3I> vt;
        std::vector<openvdb::Vec4I> vq;
        openvdb::tools::volumeToMesh(*grid, vp, vt, vq, 0.0, 0.0);
        if (vp.empty()) return;

        // Triangles (quads split along a fixed diagonal), made counter-clockwise outward.
        std::vector<std::array<std::uint32_t, 3>> tris;
        for (const auto& t : vt) tris.push_back({t[0], t[1], t[2]});
        for (const auto& q : vq) {
            tris.push_back({q[0], q[1], q[2]});
            tris.push_back({q[0], q[2], q[3]});
        }
        std::vector<glm::dvec3> pos(vp.size());
        for (std::size_t i = 0; i < vp.size(); ++i) pos[i] = {vp[i][0], vp[i][1], vp[i][2]};
        double signedVolume = 0.0;
        for (const auto& t : tris) signedVolume += glm::dot(pos[t[0]], glm::cross(pos[t[1]], pos[t[2]]));
        if (signedVolume < 0.0)
            for (auto& t : tris) std::swap(t[1], t[2]);

        // Islands: triangles connected through shared vertices.
        std::vector<std::uint32_t> parent(pos.size());
        std::iota(parent.begin(), parent.end(), 0u);
        auto find = [&](std::uint32_t x) {
            while (parent[x] != x) x = parent[x] = parent[parent[x]];
            return x;
        };
        for (const auto& t : tris)
            for (int e = 1; e < 3; ++e) {
                const std::uint32_t a = find(t[0]), b = find(t[std::size_t(e)]);
                if (a != b) parent[std::max(a, b)] = std::min(a, b);
            }
        std::map<std::uint32_t, std::vector<std::size_t>> islands;
        for (std::size_t t = 0; t < tris.size(); ++t) islands[find(tris[t][0])].push_back(t);

        for (auto& [root, members] : islands) {
            RoughPiece piece;
            std::vector<glm::dvec3> normals(pos.size(), glm::dvec3(0.0));
            for (std::size_t t : members) {
                const auto& tri = tris[t];
                const glm::dvec3 n = glm::cross(pos[tri[1]] - pos[tri[0]], pos[tri[2]] - pos[tri[0]]);
                for (std::uint32_t i : tri) normals[i] += n;
            }
            std::vector<std::uint32_t> index(pos.size(), UINT32_MAX);
            for (std::size_t t : members) {
                const auto& tri = tris[t];
                const glm::dvec3 centroid = (pos[tri[0]] + pos[tri[1]] + pos[tri[2]]) / 3.0;
                const openvdb::Vec3d ijk = xform->worldToIndex(openvdb::Vec3d(centroid.x, centroid.y, centroid.z));
                const double meshPhi = meshAccessor.getValue(openvdb::Coord::round(ijk));
                std::size_t which = 0;
                const double planePhi = field.planes(centroid, &which);
                const bool cut = planePhi > meshPhi;  // the plane term bounds the piece here
                piece.triangleKeys.push_back(cut ? cells[c].planes[which].neighbour : -1);
                const std::uint8_t material = cut ? s.interiorMaterial : surfaceMaterial;
                for (std::uint32_t i : tri) {
                    if (index[i] == UINT32_MAX || piece.mesh.materialIds[index[i]] != material) {
                        index[i] = std::uint32_t(piece.mesh.positions.size());
                        const glm::dvec3 n = glm::length(normals[i]) > 0 ? glm::normalize(normals[i]) : glm::dvec3(0, 1, 0);
                        piece.mesh.positions.push_back(glm::vec3(pos[i]));
                        piece.mesh.normals.push_back(glm::vec3(n));
                        // Planar UVs in metres on the plane the normal faces most.
                        const glm::dvec3 a = glm::abs(n);
                        const glm::dvec2 uv = a.x >= a.y && a.x >= a.z ? glm::dvec2(pos[i].z, pos[i].y)
                                              : a.y >= a.z             ? glm::dvec2(pos[i].x, pos[i].z)
                                                                       : glm::dvec2(pos[i].x, pos[i].y);
                        piece.mesh.uv0.push_back(glm::vec2(uv / s.uvScale));
                        piece.mesh.materialIds.push_back(material);
                    }
                    piece.mesh.indices.push_back(index[i]);
                }
            }
            out[c].push_back(std::move(piece));
        }
    });
    return out;
}

}  // namespace dawnforge::sim::detail
