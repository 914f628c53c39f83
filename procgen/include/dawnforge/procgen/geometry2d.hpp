#pragma once
// Plan (2D) geometry shared by every procgen stage. Plan coordinates are metres, x east,
// y north; a plan point (x, y) at height h is the glTF point (x, h, -y) (+Y up, north is
// -Z). Polygons are simple, counter-clockwise seen from above, without a repeated last
// vertex. All plan arithmetic is in double so that a tile and the whole city agree.
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/geometric.hpp>

#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <utility>
#include <vector>

namespace dawnforge::procgen {

using Polygon2 = std::vector<glm::dvec2>;

// The glTF position of plan point p at height h.
inline glm::vec3 toWorld(glm::dvec2 p, double h) {
    return {static_cast<float>(p.x), static_cast<float>(h), static_cast<float>(-p.y)};
}

// The 2D cross product (z of the 3D one): > 0 when b turns counter-clockwise from a.
inline double cross(glm::dvec2 a, glm::dvec2 b) { return a.x * b.y - a.y * b.x; }
// The unit normal on the left of a -> b: it points inside a counter-clockwise polygon.
inline glm::dvec2 inwardNormal(glm::dvec2 a, glm::dvec2 b) {
    const glm::dvec2 u = glm::normalize(b - a);
    return {-u.y, u.x};
}

double signedArea(std::span<const glm::dvec2> polygon);  // > 0 when counter-clockwise
glm::dvec2 centroid(std::span<const glm::dvec2> polygon);  // area centroid
double perimeter(std::span<const glm::dvec2> polygon);
bool containsPoint(std::span<const glm::dvec2> polygon, glm::dvec2 p);  // even-odd rule
bool isConvex(std::span<const glm::dvec2> polygon);
// The first vertex whose corner turns clockwise (beyond rounding); polygon.size() when none.
std::size_t reflexVertex(std::span<const glm::dvec2> polygon);
bool isSimple(std::span<const glm::dvec2> polygon);  // no two non-adjacent edges meet
// A point strictly inside a simple counter-clockwise polygon: the centroid of its largest triangle.
glm::dvec2 interiorPoint(std::span<const glm::dvec2> polygon);
// Whether the segments p1-p2 and q1-q2 cross at a point inside both (touching is no crossing).
bool segmentsCross(glm::dvec2 p1, glm::dvec2 p2, glm::dvec2 q1, glm::dvec2 q2);
// The point of the segment a-b nearest p.
glm::dvec2 closestOnSegment(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b);
// Distance from p to the segment a-b.
double distanceToSegment(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b);
// Distance from p to the polygon's boundary.
double distanceToBoundary(std::span<const glm::dvec2> polygon, glm::dvec2 p);

// The part of a convex polygon where dot(n, p) <= d (Sutherland-Hodgman); may be empty.
Polygon2 clipHalfPlane(std::span<const glm::dvec2> convex, glm::dvec2 n, double d);
// The part of a convex polygon where lo <= dot(axis, p) <= hi; may be empty.
Polygon2 clipStrip(std::span<const glm::dvec2> convex, glm::dvec2 axis, double lo, double hi);
// Where the line dot(axis, p) = value crosses a convex polygon, as the range of dot(other, p)
// along it; nullopt when the line misses the polygon or only touches a corner.
std::optional<std::pair<double, double>> chord(std::span<const glm::dvec2> convex, glm::dvec2 axis, double value,
                                               glm::dvec2 other);
// Distance from p along unit `dir` to where the ray leaves a convex polygon; 0 when p is past it.
double rayExit(std::span<const glm::dvec2> convex, glm::dvec2 p, glm::dvec2 dir);
// A convex polygon moved inward by `distance` along each edge's normal (outward when
// negative), corners mitred; `distance` must be small against the edges.
Polygon2 mitreOffset(std::span<const glm::dvec2> convex, double distance);
// Drops vertices of a convex polygon, one end of its shortest edge at a time (the end whose
// loss costs less area; the polygon only shrinks), until every edge is at least `minEdge`
// long or three vertices are left.
Polygon2 dropShortEdges(Polygon2 convex, double minEdge);
// Removes consecutive vertices closer than `epsilon` and vertices whose edges are
// collinear within `epsilon` (distance of the vertex from its neighbours' chord).
Polygon2 simplifyPolygon(std::span<const glm::dvec2> polygon, double epsilon = 1e-6);

// The polygon shrunk by `distance` (> 0) through CGAL's straight-skeleton offset; empty
// when nothing is left; when the offset splits the polygon, the largest part.
Polygon2 insetPolygon(std::span<const glm::dvec2> polygon, double distance);

// Triangles (three indices each, counter-clockwise) covering a simple counter-clockwise
// polygon, by ear clipping; deterministic. Empty for fewer than three vertices.
std::vector<std::uint32_t> triangulatePolygon(std::span<const glm::dvec2> polygon);

// Oriented frame of a polygon: unit axis `u` along the given edge, `v` its inward normal
// (u rotated +90 degrees), and the polygon's extents along both from `origin`.
struct PolygonFrame {
    glm::dvec2 origin{0.0};
    glm::dvec2 u{1.0, 0.0};
    glm::dvec2 v{0.0, 1.0};
    double uMin = 0, uMax = 0, vMin = 0, vMax = 0;
    glm::dvec2 toPlan(double a, double b) const { return origin + a * u + b * v; }
    glm::dvec2 toFrame(glm::dvec2 p) const { return {glm::dot(p - origin, u), glm::dot(p - origin, v)}; }
};
PolygonFrame edgeFrame(std::span<const glm::dvec2> polygon, std::size_t edge);

// The edge i (polygon[i] -> polygon[i + 1]) with the highest score(polygon[i], polygon[i + 1],
// unit direction); the first of equal scores; 0 when no score is above -infinity. Buildings
// pick the edge facing a street this way, each with its own rule for "facing".
template <class Score>
std::size_t bestEdge(std::span<const glm::dvec2> polygon, Score score) {
    std::size_t best = 0;
    double bestScore = -std::numeric_limits<double>::infinity();
    for (std::size_t i = 0, n = polygon.size(); i < n; ++i) {
        const glm::dvec2 a = polygon[i], b = polygon[(i + 1) % n];
        const double s = score(a, b, glm::normalize(b - a));
        if (s > bestScore) bestScore = s, best = i;
    }
    return best;
}

}  // namespace dawnforge::procgen
