#include "pieces.hpp"

#include "contact.hpp"
#include "piece_surface.hpp"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <array>
#include <map>
#include <optional>

namespace dawnforge::sim::detail {

namespace {

std::vector<CutFace> cutFaces(std::span<const RawPiece> pieces) {
    std::vector<CutFace> faces;
    for (std::uint32_t i = 0; i < pieces.size(); ++i) {
        const RawPiece& p = pieces[i];
        for (std::size_t t = 0; t < p.planes.size(); ++t)
            if (p.planes[t] != kSurface)
                faces.push_back({i, p.planes[t], p.points[p.pointIndices[3 * t]], p.points[p.pointIndices[3 * t + 1]],
                                 p.points[p.pointIndices[3 * t + 2]]});
    }
    return faces;
}

using Corners = std::array<glm::dvec3, 3>;

Corners sortedCorners(const RawPiece& p, std::size_t t) {
    Corners c{p.points[p.pointIndices[3 * t]], p.points[p.pointIndices[3 * t + 1]], p.points[p.pointIndices[3 * t + 2]]};
    std::sort(c.begin(), c.end(), [](const glm::dvec3& a, const glm::dvec3& b) {
        return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z);
    });
    return c;
}

struct CornerLess {
    bool operator()(const Corners& a, const Corners& b) const {
        for (std::size_t i = 0; i < 3; ++i)
            if (a[i] != b[i]) return std::tie(a[i].x, a[i].y, a[i].z) < std::tie(b[i].x, b[i].y, b[i].z);
        return false;
    }
};

// Every directed edge, welded by exact position, is walked once and its reverse once.
bool closed(const RawPiece& p) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> used;
    for (std::size_t t = 0; 3 * t < p.pointIndices.size(); ++t)
        for (std::size_t k = 0; k < 3; ++k) ++used[{p.pointIndices[3 * t + k], p.pointIndices[3 * t + (k + 1) % 3]}];
    return std::all_of(used.begin(), used.end(), [&](const auto& e) {
        const auto back = used.find({e.first.second, e.first.first});
        return e.second == 1 && back != used.end() && back->second == 1;
    });
}

// `a` and `b` as one piece without the triangles they share (corner for corner, facing
// apart); empty when they share none.
std::optional<RawPiece> joined(const RawPiece& a, const RawPiece& b, double density) {
    std::map<Corners, std::size_t, CornerLess> inB;
    for (std::size_t t = 0; t < b.planes.size(); ++t)
        if (b.planes[t] != kSurface) inB.emplace(sortedCorners(b, t), t);
    std::vector<char> dropA(a.planes.size(), 0), dropB(b.planes.size(), 0);
    bool any = false;
    for (std::size_t t = 0; t < a.planes.size(); ++t) {
        if (a.planes[t] == kSurface) continue;
        const auto it = inB.find(sortedCorners(a, t));
        if (it == inB.end() || dropB[it->second]) continue;
        dropA[t] = dropB[it->second] = 1;
        any = true;
    }
    if (!any) return std::nullopt;
    RawPiece out;
    out.mesh.name = a.mesh.name;
    out.cell = std::min(a.cell, b.cell);
    out.level = std::min(a.level, b.level);
    out.part = a.part;
    std::map<std::array<double, 3>, std::uint32_t> pointOf;
    auto append = [&](const RawPiece& p, const std::vector<char>& drop) {
        std::vector<std::uint32_t> vertexMap(p.mesh.positions.size(), UINT32_MAX);
        for (std::size_t t = 0; t < p.planes.size(); ++t) {
            if (drop[t]) continue;
            out.planes.push_back(p.planes[t]);
            for (std::size_t k = 0; k < 3; ++k) {
                const std::uint32_t v = p.mesh.indices[3 * t + k];
                if (vertexMap[v] == UINT32_MAX) {
                    vertexMap[v] = std::uint32_t(out.mesh.positions.size());
                    out.mesh.positions.push_back(p.mesh.positions[v]);
                    out.mesh.normals.push_back(p.mesh.normals[v]);
                    out.mesh.uv0.push_back(p.mesh.uv0[v]);
                    out.mesh.materialIds.push_back(p.mesh.materialIds[v]);
                    out.worldPositions.push_back(p.worldPositions[v]);
                }
                out.mesh.indices.push_back(vertexMap[v]);
                const glm::dvec3& q = p.points[p.pointIndices[3 * t + k]];
                const auto [it, inserted] = pointOf.try_emplace({q.x, q.y, q.z}, std::uint32_t(out.points.size()));
                if (inserted) out.points.push_back(q);
                out.pointIndices.push_back(it->second);
            }
        }
    };
    append(a, dropA);
    append(b, dropB);
    if (!closed(out)) return std::nullopt;
    out.mass = computeMassProperties(out.points, out.pointIndices, density);
    return out;
}

// Per axis, the power-of-two spacing whose multiples up to `reach` are exact floats.
glm::dvec3 floatGrid(const glm::dvec3& reach) {
    glm::dvec3 h;
    for (int axis = 0; axis < 3; ++axis) h[axis] = std::ldexp(1.0, std::ilogb(std::max(reach[axis], 1e-30)) + 1 - 24);
    return h;
}

// The attributes of corner `attr` of a cleaned part: a vertex of `p`, or one a flip made on
// an edge, interpolated.
struct Attributes {
    glm::vec3 normal{0.0f};
    glm::vec2 uv{0.0f};
    std::uint8_t material = 0;
};
Attributes attributesOf(const RawPiece& p, const std::vector<DerivedCorner>& derived, std::uint32_t attr) {
    if (!(attr & kDerived)) return {p.mesh.normals[attr], p.mesh.uv0[attr], p.mesh.materialIds[attr]};
    const DerivedCorner& d = derived[attr & ~kDerived];
    const Attributes a = attributesOf(p, derived, d.from), b = attributesOf(p, derived, d.to);
    const float t = float(d.t);
    const glm::vec3 n = a.normal + (b.normal - a.normal) * t;
    return {glm::length(n) > 0.0f ? glm::normalize(n) : a.normal, a.uv + (b.uv - a.uv) * t, a.material};
}

// One cleaned part of `p` as a piece on the rounding grid (h, relative to `pivot`).
RawPiece partPiece(const RawPiece& p, const std::vector<GridTriangle>& part, const CleanSurface& clean,
                   std::span<const glm::i64vec3> keys, const glm::dvec3& pivot, const glm::dvec3& h, double density) {
    RawPiece out;
    out.mesh.name = p.mesh.name;
    out.cell = p.cell;
    out.level = p.level;
    out.part = p.part;
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> vertexOf;  // (attributes, point)
    std::map<std::uint32_t, std::uint32_t> pointOf;
    for (const GridTriangle& t : part) {
        out.planes.push_back(p.planes[std::size_t(t.origin)]);
        for (std::size_t k = 0; k < 3; ++k) {
            const glm::dvec3 local = glm::dvec3(keys[t.v[k]]) * h;
            const auto [v, newVertex] = vertexOf.try_emplace({t.attr[k], t.v[k]}, std::uint32_t(out.mesh.positions.size()));
            if (newVertex) {
                const Attributes a = attributesOf(p, clean.derived, t.attr[k]);
                out.mesh.positions.push_back(glm::vec3(local));
                out.mesh.normals.push_back(a.normal);
                out.mesh.uv0.push_back(a.uv);
                out.mesh.materialIds.push_back(a.material);
                out.worldPositions.push_back(pivot + local);
            }
            out.mesh.indices.push_back(v->second);
            const auto [q, newPoint] = pointOf.try_emplace(t.v[k], std::uint32_t(out.points.size()));
            if (newPoint) out.points.push_back(pivot + local);
            out.pointIndices.push_back(q->second);
        }
    }
    out.mass = computeMassProperties(out.points, out.pointIndices, density);
    return out;
}

// The nearest float point. Through a volatile store: GCC 12's SLP vectorizer (-O2 and up) drops
// a double -> float -> double conversion that is never stored, so glm::dvec3(glm::vec3(p))
// returned p unrounded in Release builds (and rounded at -O1).
glm::dvec3 floatPoint(const glm::dvec3& p) {
    volatile float f[3] = {float(p.x), float(p.y), float(p.z)};
    return {double(f[0]), double(f[1]), double(f[2])};
}

// `p` rounded for the files, as one piece or, where rounding made it touch itself, several.
void roundPiece(const RawPiece& p, double density, bool resplit, std::vector<RawPiece>& out) {
    const glm::dvec3 pivot = floatPoint(p.mass.centerOfMass);
    glm::dvec3 reach(0.0);
    for (const glm::dvec3& q : p.points) reach = glm::max(reach, glm::abs(q - pivot));
    const glm::dvec3 h = floatGrid(reach);
    std::vector<glm::i64vec3> keys;
    std::map<std::array<std::int64_t, 3>, std::uint32_t> idOf;
    std::vector<std::uint32_t> pointId(p.points.size());
    for (std::size_t i = 0; i < p.points.size(); ++i) {
        const glm::dvec3 k = glm::round((p.points[i] - pivot) / h);
        const auto [it, inserted] = idOf.try_emplace({std::int64_t(k.x), std::int64_t(k.y), std::int64_t(k.z)},
                                                     std::uint32_t(keys.size()));
        if (inserted) keys.emplace_back(k);
        pointId[i] = it->second;
    }
    std::vector<GridTriangle> tris;
    for (std::size_t t = 0; t < p.planes.size(); ++t) {
        GridTriangle g{{}, std::int64_t(t), {}};
        for (std::size_t k = 0; k < 3; ++k) {
            g.v[k] = pointId[p.pointIndices[3 * t + k]];
            g.attr[k] = p.mesh.indices[3 * t + k];
        }
        tris.push_back(g);
    }
    const CleanSurface clean = cleanSurface(keys, std::move(tris));
    for (const std::vector<GridTriangle>& part : clean.parts) {
        RawPiece piece = partPiece(p, part, clean, keys, pivot, h, density);
        if (clean.parts.size() > 1 && resplit) {  // a part's own centre of mass is its pivot
            roundPiece(piece, density, false, out);
            continue;
        }
        piece.pivot = pivot;
        piece.mass.centerOfMass = pivot;
        out.push_back(std::move(piece));
    }
}

}  // namespace

std::vector<RawPiece> roundForFiles(std::vector<RawPiece> pieces, double density) {
    std::vector<std::vector<RawPiece>> rounded(pieces.size());
    tbb::parallel_for(std::size_t(0), pieces.size(), [&](std::size_t i) {
        roundPiece(pieces[i], density, true, rounded[i]);
        pieces[i] = RawPiece();
    });
    std::vector<RawPiece> out;
    for (std::vector<RawPiece>& list : rounded)
        for (RawPiece& p : list) out.push_back(std::move(p));
    return out;
}

std::vector<Bond> bondsBetween(std::span<const RawPiece> pieces, double minArea) {
    std::vector<Bond> bonds;
    for (const Contact& c : contacts(cutFaces(pieces), minArea)) bonds.push_back({c.a, c.b, c.area, c.centroid, c.normal});
    return bonds;
}

std::size_t mergeSmallPieces(std::vector<RawPiece>& pieces, double minVolume, double density, double minArea) {
    std::size_t merged = 0;
    std::vector<char> stuck(pieces.size(), 0);  // slivers no neighbour could take
    for (;;) {
        std::size_t smallest = pieces.size();
        for (std::size_t i = 0; i < pieces.size(); ++i)
            if (!stuck[i] && pieces[i].mass.volume < minVolume &&
                (smallest == pieces.size() || pieces[i].mass.volume < pieces[smallest].mass.volume))
                smallest = i;
        if (smallest == pieces.size()) return merged;
        std::vector<Bond> bonds = bondsBetween(pieces, minArea);
        std::stable_sort(bonds.begin(), bonds.end(), [](const Bond& x, const Bond& y) { return x.area > y.area; });
        bool done = false;
        for (const Bond& b : bonds) {
            if (b.a != smallest && b.b != smallest) continue;
            const std::size_t into = b.a == smallest ? b.b : b.a;
            if (pieces[into].part != pieces[smallest].part) continue;
            std::optional<RawPiece> whole = joined(pieces[into], pieces[smallest], density);
            if (!whole) continue;
            pieces[into] = std::move(*whole);
            pieces.erase(pieces.begin() + std::ptrdiff_t(smallest));
            stuck.erase(stuck.begin() + std::ptrdiff_t(smallest));
            ++merged;
            done = true;
            break;
        }
        if (!done) stuck[smallest] = 1;
    }
}

}  // namespace dawnforge::sim::detail
