// Roofs as closed solids. Hip roofs lift CGAL's interior straight skeleton by offset time
// (Aichholzer, Aurenhammer, Alberts, Gärtner, "A novel type of skeleton for polygons",
// 1995: a skeleton vertex at offset time t lies at height pitch * t). CGAL 5.5 has no
// skeleton extrusion and no weighted skeleton, so gables are built as the lower envelope of
// the sloped edges' planes (on a convex footprint the hip roof is the lower envelope of
// every edge's plane; leaving the gable ends out makes them vertical).
#include <dawnforge/procgen/roof.hpp>

#include <dawnforge/core/error.hpp>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/create_straight_skeleton_2.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

namespace dawnforge::procgen {

const char* roofTypeName(RoofType type) {
    switch (type) {
        case RoofType::Flat: return "flat";
        case RoofType::Hip: return "hip";
        case RoofType::Gable: return "gable";
        case RoofType::Shed: return "shed";
    }
    DAWNFORGE_ASSERT(false, "unknown roof type");
    return "";
}

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

glm::dvec3 worldD(glm::dvec2 p, double h) { return {p.x, h, -p.y}; }  // toWorld in double

// uv = (dot(P - origin, u), dot(P - origin, v)) for the world point P, in metres.
struct FaceUv {
    glm::dvec3 origin{0.0};
    glm::dvec3 u{1.0, 0.0, 0.0};
    glm::dvec3 v{0.0, 0.0, -1.0};
};
FaceUv planUv() { return {}; }  // flat faces: plan x, y
FaceUv wallUv(glm::dvec2 a, glm::dvec2 b) {  // u along a->b, v = height
    const glm::dvec2 u = glm::normalize(b - a);
    return {worldD(a, 0.0), {u.x, 0.0, -u.y}, {0.0, 1.0, 0.0}};
}
// A plane rising with `pitch` in plan direction `up` from the eave line through `eave`
// (at height h) running along `along`: u along the eave, v up the slope.
FaceUv slopeUv(glm::dvec2 eave, double h, glm::dvec2 along, glm::dvec2 up, double pitch) {
    return {worldD(eave, h), {along.x, 0.0, -along.y}, glm::normalize(glm::dvec3(up.x, pitch, -up.y))};
}

struct Face {
    std::vector<std::uint32_t> loop;  // point indices, counter-clockwise seen from outside
    std::uint8_t material = 0;
    FaceUv uv;
};

// A closed solid under construction: every point is computed once, so that faces sharing
// an edge share bit-identical positions.
struct Solid {
    std::vector<glm::dvec2> plan;
    std::vector<double> height;
    std::vector<Face> faces;

    std::uint32_t add(glm::dvec2 p, double h) {
        plan.push_back(p);
        height.push_back(h);
        return static_cast<std::uint32_t>(plan.size() - 1);
    }
    void face(std::vector<std::uint32_t> loop, std::uint8_t material, const FaceUv& uv) {
        faces.push_back({std::move(loop), material, uv});
    }
};

std::vector<std::uint32_t> withoutRepeats(std::vector<std::uint32_t> loop) {
    std::vector<std::uint32_t> out;
    for (std::uint32_t i : loop)
        if (out.empty() || out.back() != i) out.push_back(i);
    while (out.size() > 1 && out.front() == out.back()) out.pop_back();
    return out;
}

// Flat normals: each face gets its own vertices; faces are triangulated by ear clipping in
// their own plane.
Mesh toMesh(const Solid& solid) {
    Mesh mesh;
    mesh.name = "roof";
    std::vector<glm::vec3> world(solid.plan.size());
    std::vector<glm::dvec3> worldDouble(solid.plan.size());
    for (std::size_t i = 0; i < world.size(); ++i) {
        world[i] = toWorld(solid.plan[i], solid.height[i]);
        worldDouble[i] = worldD(solid.plan[i], solid.height[i]);
    }
    for (const Face& face : solid.faces) {
        const std::vector<std::uint32_t> loop = withoutRepeats(face.loop);
        if (loop.size() < 3) continue;
        const glm::dvec3 p0 = worldDouble[loop[0]];
        glm::dvec3 normal(0.0);  // Newell
        for (std::size_t k = 0; k < loop.size(); ++k)
            normal += glm::cross(worldDouble[loop[k]] - p0, worldDouble[loop[(k + 1) % loop.size()]] - p0);
        const double length = glm::length(normal);
        if (!(length > 0.0)) continue;
        normal /= length;
        const glm::dvec3 axis = std::abs(normal.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
        const glm::dvec3 t1 = glm::normalize(axis - normal * glm::dot(axis, normal));
        const glm::dvec3 t2 = glm::cross(normal, t1);  // t1 x t2 = normal: the loop is CCW in (t1, t2)
        Polygon2 flat;
        flat.reserve(loop.size());
        for (std::uint32_t i : loop) {
            const glm::dvec3 d = worldDouble[i] - p0;
            flat.push_back({glm::dot(d, t1), glm::dot(d, t2)});
        }
        const std::vector<std::uint32_t> triangles = triangulatePolygon(flat);
        const auto first = static_cast<std::uint32_t>(mesh.positions.size());
        for (std::uint32_t i : loop) {
            const glm::dvec3 d = worldDouble[i] - face.uv.origin;
            mesh.positions.push_back(world[i]);
            mesh.normals.push_back(glm::vec3(normal));
            mesh.uv0.push_back({static_cast<float>(glm::dot(d, face.uv.u)), static_cast<float>(glm::dot(d, face.uv.v))});
            mesh.materialIds.push_back(face.material);
        }
        for (std::uint32_t t : triangles) mesh.indices.push_back(first + t);
    }
    return mesh;
}

// Extent of the footprint's bounding box: the scale of welding tolerances.
double extent(std::span<const glm::dvec2> footprint) {
    glm::dvec2 lo(INFINITY), hi(-INFINITY);
    for (glm::dvec2 p : footprint) lo = glm::min(lo, p), hi = glm::max(hi, p);
    return std::max(hi.x - lo.x, hi.y - lo.y);
}

// The footprint (points 0..n-1 at baseHeight) and its bottom face, facing down. The bottom
// is hidden where the roof stands on its building; it takes the wall material.
Solid footprintSolid(std::span<const glm::dvec2> footprint, double baseHeight, std::uint8_t material) {
    Solid solid;
    std::vector<std::uint32_t> bottom;
    for (glm::dvec2 p : footprint) bottom.push_back(solid.add(p, baseHeight));
    std::reverse(bottom.begin(), bottom.end());
    solid.face(std::move(bottom), material, planUv());
    return solid;
}

// ---- Flat -------------------------------------------------------------------------------

// The parapet's inner outline with inner[i] the offset of footprint[i], or empty when the
// inset does not correspond vertex for vertex (an edge vanished or the outline split).
Polygon2 correspondingInset(std::span<const glm::dvec2> footprint, double width) {
    const std::size_t n = footprint.size();
    const Polygon2 inset = insetPolygon(footprint, width);
    if (inset.size() != n) return {};
    Polygon2 expected(n);  // miter points of the offset edges
    for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec2 prev = footprint[(i + n - 1) % n], p = footprint[i], next = footprint[(i + 1) % n];
        const glm::dvec2 n0 = inwardNormal(prev, p), n1 = inwardNormal(p, next);
        const double denominator = 1.0 + glm::dot(n0, n1);
        if (denominator < 1e-6) return {};
        expected[i] = p + width * (n0 + n1) / denominator;
    }
    const double tolerance = 1e-6 * std::max(1.0, extent(footprint));
    for (std::size_t shift = 0; shift < n; ++shift) {
        if (glm::distance(inset[shift], expected[0]) > tolerance) continue;
        Polygon2 inner(n);
        for (std::size_t i = 0; i < n; ++i) inner[i] = inset[(i + shift) % n];
        bool matches = true;
        for (std::size_t i = 0; i < n && matches; ++i)
            matches = glm::distance(inner[i], expected[i]) <= tolerance &&
                      glm::dot(inner[(i + 1) % n] - inner[i], footprint[(i + 1) % n] - footprint[i]) > 0.0;
        return matches ? inner : Polygon2{};
    }
    return {};
}

Roof flatRoof(std::span<const glm::dvec2> footprint, double baseHeight, const RoofSettings& settings) {
    const std::size_t n = footprint.size();
    const auto u32 = [](std::size_t i) { return static_cast<std::uint32_t>(i); };
    // The parapet's top ring is triangulated as one quad per edge between the footprint and
    // its inset, which needs the inset to keep every vertex in order (true for convex
    // footprints and for most non-convex ones at small widths). Otherwise, and without a
    // parapet, the roof is a plain slab.
    Polygon2 inner;
    if (settings.parapetHeight > 0.0 && settings.parapetWidth > 0.0)
        inner = correspondingInset(footprint, settings.parapetWidth);
    Solid solid = footprintSolid(footprint, baseHeight, settings.wallMaterial);
    const double slabTop = baseHeight + settings.slabThickness;
    if (inner.empty()) {
        for (std::size_t i = 0; i < n; ++i) solid.add(footprint[i], slabTop);
        std::vector<std::uint32_t> top;
        for (std::size_t i = 0; i < n; ++i) {
            const std::size_t j = (i + 1) % n;
            solid.face({u32(i), u32(j), u32(n + j), u32(n + i)}, settings.wallMaterial,
                       wallUv(footprint[i], footprint[j]));
            top.push_back(u32(n + i));
        }
        solid.face(std::move(top), settings.flatMaterial, planUv());
        return {toMesh(solid), settings.slabThickness};
    }
    const double parapetTop = slabTop + settings.parapetHeight;
    for (std::size_t i = 0; i < n; ++i) solid.add(footprint[i], parapetTop);  // n..2n-1
    for (std::size_t i = 0; i < n; ++i) solid.add(inner[i], parapetTop);      // 2n..3n-1
    for (std::size_t i = 0; i < n; ++i) solid.add(inner[i], slabTop);         // 3n..4n-1
    std::vector<std::uint32_t> surface;
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t j = (i + 1) % n;
        solid.face({u32(i), u32(j), u32(n + j), u32(n + i)}, settings.wallMaterial, wallUv(footprint[i], footprint[j]));
        solid.face({u32(n + i), u32(n + j), u32(2 * n + j), u32(2 * n + i)}, settings.trimMaterial, planUv());
        solid.face({u32(3 * n + j), u32(3 * n + i), u32(2 * n + i), u32(2 * n + j)}, settings.wallMaterial,
                   wallUv(inner[j], inner[i]));
        surface.push_back(u32(3 * n + i));
    }
    solid.face(std::move(surface), settings.flatMaterial, planUv());
    return {toMesh(solid), settings.slabThickness + settings.parapetHeight};
}

// ---- Hip --------------------------------------------------------------------------------

struct Skeleton {
    std::vector<glm::dvec2> nodes;  // interior vertices, welded
    std::vector<double> times;      // their offset times
    struct Face {
        std::size_t edge = 0;              // footprint edge i: footprint[i] -> footprint[i + 1]
        std::vector<std::uint32_t> loop;   // < n: footprint vertex; else n + node; CCW
    };
    std::vector<Face> faces;
    bool valid = false;
};

Skeleton straightSkeleton(std::span<const glm::dvec2> footprint) {
    const std::size_t n = footprint.size();
    // Relative to the first vertex: times and nodes far from the origin lose digits otherwise.
    const glm::dvec2 origin = footprint[0];
    std::vector<Kernel::Point_2> points;
    std::map<std::pair<double, double>, std::uint32_t> contourIndex;
    for (std::size_t i = 0; i < n; ++i) {
        points.emplace_back(footprint[i].x - origin.x, footprint[i].y - origin.y);
        contourIndex[{points.back().x(), points.back().y()}] = static_cast<std::uint32_t>(i);
    }
    Skeleton out;
    const auto ss = CGAL::create_interior_straight_skeleton_2(points.begin(), points.end(), Kernel());
    if (!ss) return out;
    // Events that coincide (the centre of a square) may come as several nodes a rounding
    // error apart: weld them so that every face uses the same point.
    const double tolerance = 1e-9 * extent(footprint);
    std::map<int, std::uint32_t> index;
    for (auto v = ss->vertices_begin(); v != ss->vertices_end(); ++v) {
        if (v->is_contour()) {
            const auto found = contourIndex.find({v->point().x(), v->point().y()});
            if (found == contourIndex.end()) return out;
            index[v->id()] = found->second;
            continue;
        }
        const glm::dvec2 p = origin + glm::dvec2(v->point().x(), v->point().y());
        const double time = v->time();
        std::size_t j = 0;
        while (j < out.nodes.size() &&
               !(glm::distance(out.nodes[j], p) <= tolerance && std::abs(out.times[j] - time) <= tolerance))
            ++j;
        if (j == out.nodes.size()) out.nodes.push_back(p), out.times.push_back(time);
        index[v->id()] = static_cast<std::uint32_t>(n + j);
    }
    const auto planOf = [&](std::uint32_t i) { return i < n ? footprint[i] : out.nodes[i - n]; };
    for (auto f = ss->faces_begin(); f != ss->faces_end(); ++f) {
        const auto start = f->halfedge();  // the face's contour edge
        const std::uint32_t a = index.at(start->opposite()->vertex()->id()), b = index.at(start->vertex()->id());
        Skeleton::Face face;
        if (a < n && b == (a + 1) % n) face.edge = a;
        else if (b < n && a == (b + 1) % n) face.edge = b;
        else return out;
        auto h = start;
        do {
            face.loop.push_back(index.at(h->vertex()->id()));
            h = h->next();
        } while (h != start);
        face.loop = withoutRepeats(std::move(face.loop));
        double area = 0.0;
        for (std::size_t k = 0; k < face.loop.size(); ++k)
            area += cross(planOf(face.loop[k]) - footprint[face.edge],
                          planOf(face.loop[(k + 1) % face.loop.size()]) - footprint[face.edge]);
        if (area < 0.0) std::reverse(face.loop.begin(), face.loop.end());
        out.faces.push_back(std::move(face));
    }
    std::sort(out.faces.begin(), out.faces.end(), [](const auto& x, const auto& y) { return x.edge < y.edge; });
    out.valid = out.faces.size() == n;
    return out;
}

Roof hipRoof(std::span<const glm::dvec2> footprint, double baseHeight, const RoofSettings& settings) {
    const std::size_t n = footprint.size();
    const Skeleton skeleton = straightSkeleton(footprint);
    DAWNFORGE_ASSERT(skeleton.valid, "CGAL's straight skeleton failed on a simple footprint");
    Solid solid = footprintSolid(footprint, baseHeight, settings.wallMaterial);
    double maxTime = 0.0;
    for (std::size_t j = 0; j < skeleton.nodes.size(); ++j) {
        solid.add(skeleton.nodes[j], baseHeight + settings.pitch * skeleton.times[j]);
        maxTime = std::max(maxTime, skeleton.times[j]);
    }
    for (const Skeleton::Face& face : skeleton.faces) {
        const glm::dvec2 a = footprint[face.edge], b = footprint[(face.edge + 1) % n];
        solid.face(face.loop, settings.roofMaterial,
                   slopeUv(a, baseHeight, glm::normalize(b - a), inwardNormal(a, b), settings.pitch));
    }
    return {toMesh(solid), settings.pitch * maxTime};
}

// ---- Gable ------------------------------------------------------------------------------

// Edges whose direction is within 60 degrees of the front edge's slope; the others are
// gable ends and get vertical walls.
std::vector<bool> slopedEdges(std::span<const glm::dvec2> footprint, std::size_t frontEdge) {
    const std::size_t n = footprint.size();
    const glm::dvec2 front = glm::normalize(footprint[(frontEdge + 1) % n] - footprint[frontEdge]);
    std::vector<bool> sloped(n);
    for (std::size_t i = 0; i < n; ++i)
        sloped[i] = std::abs(glm::dot(glm::normalize(footprint[(i + 1) % n] - footprint[i]), front)) >= 0.5;
    return sloped;
}

// The gable roof of a convex footprint as the lower envelope of the sloped edges' planes
// (height pitch * distance to the edge's line): the face of sloped edge e is the footprint
// clipped by the bisector half-planes {d_e <= d_g} of every other sloped edge g, and each
// gable-end edge gets a vertical wall up to the envelope. Empty when a face vanishes.
// (Sliding the hip skeleton's nodes onto the end walls gives the same roof when the front
// edge is the long side of a rectangle, but not when it is the short side: the ridge then
// lies at no skeleton node.)
Roof gableRoof(std::span<const glm::dvec2> footprint, double baseHeight, const RoofSettings& settings) {
    const std::size_t n = footprint.size();
    const std::vector<bool> sloped = slopedEdges(footprint, settings.frontEdge);
    // Work relative to the first vertex for precision far from the origin.
    const glm::dvec2 origin = footprint[0];
    Polygon2 local(n);
    std::vector<glm::dvec2> normals(n);
    for (std::size_t i = 0; i < n; ++i) local[i] = footprint[i] - origin;
    for (std::size_t i = 0; i < n; ++i) normals[i] = inwardNormal(local[i], local[(i + 1) % n]);
    const double tolerance = 1e-9 * extent(footprint);

    // Plan points shared by the faces, welded; the first n are the footprint's vertices.
    Polygon2 points(local.begin(), local.end());
    const auto pointIndex = [&](glm::dvec2 p) {
        std::size_t j = 0;
        while (j < points.size() && glm::distance(points[j], p) > tolerance) ++j;
        if (j == points.size()) points.push_back(p);
        return static_cast<std::uint32_t>(j);
    };
    std::vector<std::pair<std::size_t, std::vector<std::uint32_t>>> slopeFaces;
    for (std::size_t e = 0; e < n; ++e) {
        if (!sloped[e]) continue;
        Polygon2 face = local;
        for (std::size_t g = 0; g < n && !face.empty(); ++g) {
            if (!sloped[g] || g == e) continue;
            const glm::dvec2 direction = normals[e] - normals[g];
            if (glm::length(direction) < 1e-12) continue;  // collinear edges: the same plane
            face = clipHalfPlane(face, direction,
                                 glm::dot(normals[e], local[e]) - glm::dot(normals[g], local[g]));
        }
        if (face.empty()) return {};
        std::vector<std::uint32_t> loop;
        for (glm::dvec2 p : face) loop.push_back(pointIndex(p));
        slopeFaces.emplace_back(e, withoutRepeats(std::move(loop)));
    }

    // Heights: the envelope; zero (the eave) within the tolerance.
    std::vector<double> rise(points.size(), INFINITY);
    for (std::size_t k = 0; k < points.size(); ++k) {
        for (std::size_t g = 0; g < n; ++g)
            if (sloped[g]) rise[k] = std::min(rise[k], glm::dot(normals[g], points[k] - local[g]));
        if (rise[k] <= tolerance) rise[k] = 0.0;
    }
    Solid solid = footprintSolid(footprint, baseHeight, settings.wallMaterial);
    std::vector<std::uint32_t> top(points.size());
    double maxRise = 0.0;
    for (std::size_t k = 0; k < points.size(); ++k) {
        maxRise = std::max(maxRise, rise[k]);
        if (k < n && rise[k] == 0.0) top[k] = static_cast<std::uint32_t>(k);
        else if (rise[k] == 0.0) return {};  // an eave point off the footprint's corners
        else top[k] = solid.add(k < n ? footprint[k] : origin + points[k], baseHeight + settings.pitch * rise[k]);
    }
    for (const auto& [e, loop] : slopeFaces) {
        if (loop.size() < 3) return {};
        std::vector<std::uint32_t> roofLoop;
        for (std::uint32_t k : loop) roofLoop.push_back(top[k]);
        const glm::dvec2 a = footprint[e], b = footprint[(e + 1) % n];
        solid.face(std::move(roofLoop), settings.roofMaterial,
                   slopeUv(a, baseHeight, glm::normalize(b - a), normals[e], settings.pitch));
    }
    for (std::size_t g = 0; g < n; ++g) {
        if (sloped[g]) continue;
        const std::size_t h = (g + 1) % n;
        const glm::dvec2 a = local[g], direction = glm::normalize(local[h] - a);
        std::vector<std::pair<double, std::uint32_t>> profile;  // envelope points over the edge
        for (std::size_t k = 0; k < points.size(); ++k)
            if (k == g || k == h || (k >= n && distanceToSegment(points[k], a, local[h]) <= tolerance))
                profile.emplace_back(glm::dot(points[k] - a, direction), top[k]);
        std::sort(profile.begin(), profile.end());
        std::vector<std::uint32_t> wall{static_cast<std::uint32_t>(g), static_cast<std::uint32_t>(h)};
        for (auto it = profile.rbegin(); it != profile.rend(); ++it) wall.push_back(it->second);
        solid.face(std::move(wall), settings.wallMaterial, wallUv(footprint[g], footprint[h]));
    }
    return {toMesh(solid), settings.pitch * maxRise};
}

// ---- Shed -------------------------------------------------------------------------------

Roof shedRoof(std::span<const glm::dvec2> footprint, double baseHeight, const RoofSettings& settings) {
    const std::size_t n = footprint.size();
    const glm::dvec2 a = footprint[settings.frontEdge], b = footprint[(settings.frontEdge + 1) % n];
    const glm::dvec2 along = glm::normalize(b - a), inward = inwardNormal(a, b);
    std::vector<double> depth(n);  // distance from the front edge's line
    std::size_t back = 0;
    for (std::size_t i = 0; i < n; ++i) {
        depth[i] = glm::dot(footprint[i] - a, inward);
        if (depth[i] > depth[back]) back = i;
    }
    const double run = depth[back];  // from the back line to the front edge
    const double tolerance = 1e-9 * extent(footprint);
    Solid solid = footprintSolid(footprint, baseHeight, settings.wallMaterial);
    std::vector<std::uint32_t> top(n);
    // A non-convex footprint may reach past the front edge's line: the plane goes on rising.
    double maxRise = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        const double rise = run - depth[i];
        maxRise = std::max(maxRise, rise);
        // On the back line the roof meets the bottom: share the point so the solid closes.
        top[i] = rise <= tolerance ? static_cast<std::uint32_t>(i)
                                   : solid.add(footprint[i], baseHeight + settings.pitch * rise);
    }
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t j = (i + 1) % n;
        solid.face({static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j), top[j], top[i]},
                   settings.wallMaterial, wallUv(footprint[i], footprint[j]));
    }
    solid.face(top, settings.roofMaterial, slopeUv(footprint[back], baseHeight, along, -inward, settings.pitch));
    return {toMesh(solid), settings.pitch * maxRise};
}

}  // namespace

Roof buildRoof(std::span<const glm::dvec2> footprint, double baseHeight, const RoofSettings& settings) {
    DAWNFORGE_ASSERT(footprint.size() >= 3, "the footprint needs at least three vertices");
    DAWNFORGE_ASSERT(signedArea(footprint) > 0.0, "the footprint must be counter-clockwise with a non-zero area");
    DAWNFORGE_ASSERT(isSimple(footprint), "the footprint must be a simple polygon");
    switch (settings.type) {
        case RoofType::Flat:
            DAWNFORGE_ASSERT(settings.slabThickness > 0.0 && settings.parapetHeight >= 0.0 &&
                                 settings.parapetWidth >= 0.0,
                             "flat roof: slab thickness must be positive, parapet sizes non-negative");
            return flatRoof(footprint, baseHeight, settings);
        case RoofType::Hip:
            DAWNFORGE_ASSERT(settings.pitch > 0.0, "pitch must be positive");
            return hipRoof(footprint, baseHeight, settings);
        case RoofType::Gable: {
            DAWNFORGE_ASSERT(settings.pitch > 0.0, "pitch must be positive");
            DAWNFORGE_ASSERT(settings.frontEdge < footprint.size(), "frontEdge out of range");
            // Non-convex footprints (whose envelope of edge planes is not their roof), and
            // footprints without gable ends, get a hip roof.
            const std::vector<bool> sloped = slopedEdges(footprint, settings.frontEdge);
            if (!isConvex(footprint) || std::all_of(sloped.begin(), sloped.end(), [](bool s) { return s; }))
                return hipRoof(footprint, baseHeight, settings);
            Roof roof = gableRoof(footprint, baseHeight, settings);
            // Empty when rounding left a face without area (a degenerate footprint): hip.
            return roof.mesh.positions.empty() ? hipRoof(footprint, baseHeight, settings) : roof;
        }
        case RoofType::Shed:
            DAWNFORGE_ASSERT(settings.pitch > 0.0, "pitch must be positive");
            DAWNFORGE_ASSERT(settings.frontEdge < footprint.size(), "frontEdge out of range");
            return shedRoof(footprint, baseHeight, settings);
    }
    DAWNFORGE_ASSERT(false, "unknown roof type");
    return {};
}

}  // namespace dawnforge::procgen
