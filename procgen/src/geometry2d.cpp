#include <dawnforge/procgen/geometry2d.hpp>

#include <dawnforge/core/error.hpp>

#include <algorithm>
#include <cmath>

namespace dawnforge::procgen {

double signedArea(std::span<const glm::dvec2> polygon) {
    double sum = 0.0;
    for (std::size_t i = 0, n = polygon.size(); i < n; ++i) sum += cross(polygon[i], polygon[(i + 1) % n]);
    return 0.5 * sum;
}

glm::dvec2 centroid(std::span<const glm::dvec2> polygon) {
    if (polygon.empty()) return glm::dvec2(0.0);
    // Relative to the first vertex, for precision far from the origin.
    const glm::dvec2 o = polygon[0];
    double area = 0.0;
    glm::dvec2 sum(0.0);
    for (std::size_t i = 1; i + 1 < polygon.size(); ++i) {
        const glm::dvec2 a = polygon[i] - o, b = polygon[i + 1] - o;
        const double w = cross(a, b);
        area += w;
        sum += w * (a + b);
    }
    if (std::abs(area) < 1e-300) {
        glm::dvec2 mean(0.0);
        for (glm::dvec2 p : polygon) mean += p;
        return mean / static_cast<double>(polygon.size());
    }
    return o + sum / (3.0 * area);
}

double perimeter(std::span<const glm::dvec2> polygon) {
    double sum = 0.0;
    for (std::size_t i = 0, n = polygon.size(); i < n; ++i) sum += glm::distance(polygon[i], polygon[(i + 1) % n]);
    return sum;
}

bool containsPoint(std::span<const glm::dvec2> polygon, glm::dvec2 p) {
    bool inside = false;
    for (std::size_t i = 0, n = polygon.size(), j = n - 1; i < n; j = i++) {
        const glm::dvec2 a = polygon[i], b = polygon[j];
        if ((a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x) inside = !inside;
    }
    return inside;
}

bool isConvex(std::span<const glm::dvec2> polygon) {
    return polygon.size() >= 3 && reflexVertex(polygon) == polygon.size();
}

std::size_t reflexVertex(std::span<const glm::dvec2> polygon) {
    const std::size_t n = polygon.size();
    for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec2 a = polygon[(i + n - 1) % n], b = polygon[i], c = polygon[(i + 1) % n];
        if (cross(b - a, c - b) < -1e-12 * glm::length(b - a) * glm::length(c - b)) return i;
    }
    return n;
}

glm::dvec2 interiorPoint(std::span<const glm::dvec2> polygon) {
    const std::vector<std::uint32_t> triangles = triangulatePolygon(polygon);
    glm::dvec2 best = polygon[0];
    double bestArea = -1.0;
    for (std::size_t t = 0; t + 2 < triangles.size(); t += 3) {
        const glm::dvec2 a = polygon[triangles[t]], b = polygon[triangles[t + 1]], c = polygon[triangles[t + 2]];
        const double area = cross(b - a, c - a);
        if (area > bestArea) bestArea = area, best = (a + b + c) / 3.0;
    }
    return best;
}

namespace {
bool oppositeSigns(double x, double y) { return (x > 0.0 && y < 0.0) || (x < 0.0 && y > 0.0); }

bool segmentsIntersect(glm::dvec2 p1, glm::dvec2 p2, glm::dvec2 q1, glm::dvec2 q2) {
    const double d1 = cross(q2 - q1, p1 - q1), d2 = cross(q2 - q1, p2 - q1);
    const double d3 = cross(p2 - p1, q1 - p1), d4 = cross(p2 - p1, q2 - p1);
    if (oppositeSigns(d1, d2) && oppositeSigns(d3, d4)) return true;
    auto onSegment = [](glm::dvec2 a, glm::dvec2 b, glm::dvec2 p) {
        return std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y &&
               p.y <= std::max(a.y, b.y);
    };
    return (d1 == 0 && onSegment(q1, q2, p1)) || (d2 == 0 && onSegment(q1, q2, p2)) ||
           (d3 == 0 && onSegment(p1, p2, q1)) || (d4 == 0 && onSegment(p1, p2, q2));
}
}  // namespace

bool isSimple(std::span<const glm::dvec2> polygon) {
    const std::size_t n = polygon.size();
    if (n < 3) return false;
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 1; j < n; ++j) {
            if (j == i + 1 || (i == 0 && j == n - 1)) continue;  // adjacent edges share a vertex
            if (segmentsIntersect(polygon[i], polygon[(i + 1) % n], polygon[j], polygon[(j + 1) % n])) return false;
        }
    return true;
}

bool segmentsCross(glm::dvec2 p1, glm::dvec2 p2, glm::dvec2 q1, glm::dvec2 q2) {
    const double d1 = cross(q2 - q1, p1 - q1), d2 = cross(q2 - q1, p2 - q1);
    const double d3 = cross(p2 - p1, q1 - p1), d4 = cross(p2 - p1, q2 - p1);
    return oppositeSigns(d1, d2) && oppositeSigns(d3, d4);
}

glm::dvec2 closestOnSegment(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b) {
    const glm::dvec2 ab = b - a;
    const double len2 = glm::dot(ab, ab);
    return len2 > 0.0 ? a + ab * std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : a;
}

double distanceToSegment(glm::dvec2 p, glm::dvec2 a, glm::dvec2 b) {
    return glm::distance(p, closestOnSegment(p, a, b));
}

double distanceToBoundary(std::span<const glm::dvec2> polygon, glm::dvec2 p) {
    double best = INFINITY;
    for (std::size_t i = 0, n = polygon.size(); i < n; ++i)
        best = std::min(best, distanceToSegment(p, polygon[i], polygon[(i + 1) % n]));
    return best;
}

Polygon2 clipHalfPlane(std::span<const glm::dvec2> convex, glm::dvec2 n, double d) {
    Polygon2 out;
    const std::size_t count = convex.size();
    out.reserve(count + 1);
    for (std::size_t i = 0; i < count; ++i) {
        const glm::dvec2 a = convex[i], b = convex[(i + 1) % count];
        const double da = glm::dot(n, a) - d, db = glm::dot(n, b) - d;
        if (da <= 0.0) out.push_back(a);
        if ((da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0)) out.push_back(a + (b - a) * (da / (da - db)));
    }
    if (out.size() < 3) out.clear();
    return out;
}

Polygon2 clipStrip(std::span<const glm::dvec2> convex, glm::dvec2 axis, double lo, double hi) {
    Polygon2 piece = clipHalfPlane(convex, axis, hi);
    if (!piece.empty()) piece = clipHalfPlane(piece, -axis, -lo);
    return piece;
}

std::optional<std::pair<double, double>> chord(std::span<const glm::dvec2> convex, glm::dvec2 axis, double value,
                                               glm::dvec2 other) {
    constexpr double kOnLine = 1e-7;  // vertices this close count as on the line (clipping leaves ~1e-15)
    double lo = INFINITY, hi = -INFINITY;
    auto take = [&](glm::dvec2 p) {
        lo = std::min(lo, glm::dot(p, other));
        hi = std::max(hi, glm::dot(p, other));
    };
    for (std::size_t i = 0, n = convex.size(); i < n; ++i) {
        const glm::dvec2 a = convex[i], b = convex[(i + 1) % n];
        const double da = glm::dot(a, axis) - value, db = glm::dot(b, axis) - value;
        if (std::abs(da) <= kOnLine) take(a);
        if ((da < -kOnLine && db > kOnLine) || (da > kOnLine && db < -kOnLine)) take(a + (b - a) * (da / (da - db)));
    }
    if (!(hi > lo)) return std::nullopt;
    return std::make_pair(lo, hi);
}

double rayExit(std::span<const glm::dvec2> convex, glm::dvec2 p, glm::dvec2 dir) {
    double best = INFINITY;
    for (std::size_t i = 0, n = convex.size(); i < n; ++i) {
        const glm::dvec2 a = convex[i], b = convex[(i + 1) % n];
        const glm::dvec2 e = b - a, outN{e.y, -e.x};
        const double denom = glm::dot(dir, outN);
        if (denom <= 1e-12) continue;
        best = std::min(best, glm::dot(a - p, outN) / denom);
    }
    return std::max(0.0, best);
}

Polygon2 mitreOffset(std::span<const glm::dvec2> convex, double distance) {
    const std::size_t n = convex.size();
    Polygon2 out(n);
    for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec2 p = convex[(i + n - 1) % n], c = convex[i], q = convex[(i + 1) % n];
        const glm::dvec2 n0 = inwardNormal(p, c), n1 = inwardNormal(c, q);
        // c + x with dot(x, n0) = dot(x, n1) = distance.
        const double det = cross(n0, n1);
        const glm::dvec2 x(distance * n1.y - distance * n0.y, n0.x * distance - n1.x * distance);
        out[i] = std::abs(det) < 1e-12 ? c + n0 * distance : c + x / det;
    }
    return out;
}

Polygon2 dropShortEdges(Polygon2 convex, double minEdge) {
    while (convex.size() > 3) {
        const std::size_t n = convex.size();
        std::size_t worst = n;
        double shortest = minEdge;
        for (std::size_t i = 0; i < n; ++i) {
            const double length = glm::distance(convex[i], convex[(i + 1) % n]);
            if (length < shortest) shortest = length, worst = i;
        }
        if (worst == n) break;
        // Remove whichever end of the short edge costs less area.
        auto cost = [&](std::size_t i) {
            const glm::dvec2 prev = convex[(i + n - 1) % n];
            return std::abs(cross(convex[i] - prev, convex[(i + 1) % n] - prev));
        };
        const std::size_t a = worst, b = (worst + 1) % n;
        convex.erase(convex.begin() + static_cast<std::ptrdiff_t>(cost(a) <= cost(b) ? a : b));
    }
    return convex;
}

Polygon2 simplifyPolygon(std::span<const glm::dvec2> polygon, double epsilon) {
    Polygon2 out(polygon.begin(), polygon.end());
    bool changed = true;
    while (changed && out.size() >= 3) {
        changed = false;
        for (std::size_t i = 0; i < out.size() && out.size() >= 3; ++i) {
            const std::size_t n = out.size();
            const glm::dvec2 prev = out[(i + n - 1) % n], cur = out[i], next = out[(i + 1) % n];
            if (glm::distance(cur, next) < epsilon || distanceToSegment(cur, prev, next) < epsilon) {
                out.erase(out.begin() + static_cast<std::ptrdiff_t>(i));
                changed = true;
                --i;
            }
        }
    }
    if (out.size() < 3) out.clear();
    return out;
}

std::vector<std::uint32_t> triangulatePolygon(std::span<const glm::dvec2> polygon) {
    std::vector<std::uint32_t> out;
    const std::size_t n = polygon.size();
    if (n < 3) return out;
    out.reserve(3 * (n - 2));
    std::vector<std::uint32_t> ring(n);
    for (std::size_t i = 0; i < n; ++i) ring[i] = static_cast<std::uint32_t>(i);
    auto isEar = [&](std::size_t i) {
        const std::size_t m = ring.size();
        const glm::dvec2 a = polygon[ring[(i + m - 1) % m]], b = polygon[ring[i]], c = polygon[ring[(i + 1) % m]];
        if (cross(b - a, c - b) <= 0.0) return false;  // reflex or flat corner
        for (std::size_t j = 0; j < m; ++j) {
            if (j == i || j == (i + 1) % m || j == (i + m - 1) % m) continue;
            const glm::dvec2 p = polygon[ring[j]];
            if (p == a || p == b || p == c) continue;
            if (cross(b - a, p - a) >= 0.0 && cross(c - b, p - b) >= 0.0 && cross(a - c, p - c) >= 0.0) return false;
        }
        return true;
    };
    while (ring.size() > 3) {
        std::size_t m = ring.size(), ear = m;
        for (std::size_t i = 0; i < m && ear == m; ++i)
            if (isEar(i)) ear = i;
        if (ear == m) {
            // Only flat or nearly flat corners left (rounding): cut the flattest one.
            double best = INFINITY;
            for (std::size_t i = 0; i < m; ++i) {
                const glm::dvec2 a = polygon[ring[(i + m - 1) % m]], b = polygon[ring[i]], c = polygon[ring[(i + 1) % m]];
                const double turn = std::abs(cross(b - a, c - b));
                if (turn < best) best = turn, ear = i;
            }
        }
        out.insert(out.end(), {ring[(ear + m - 1) % m], ring[ear], ring[(ear + 1) % m]});
        ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(ear));
    }
    out.insert(out.end(), {ring[0], ring[1], ring[2]});
    return out;
}

PolygonFrame edgeFrame(std::span<const glm::dvec2> polygon, std::size_t edge) {
    DAWNFORGE_ASSERT(polygon.size() >= 3 && edge < polygon.size(), "edge out of range");
    PolygonFrame frame;
    frame.origin = polygon[edge];
    frame.u = glm::normalize(polygon[(edge + 1) % polygon.size()] - polygon[edge]);
    frame.v = {-frame.u.y, frame.u.x};
    frame.uMin = frame.vMin = INFINITY;
    frame.uMax = frame.vMax = -INFINITY;
    for (glm::dvec2 p : polygon) {
        const glm::dvec2 f = frame.toFrame(p);
        frame.uMin = std::min(frame.uMin, f.x);
        frame.uMax = std::max(frame.uMax, f.x);
        frame.vMin = std::min(frame.vMin, f.y);
        frame.vMax = std::max(frame.vMax, f.y);
    }
    return frame;
}

}  // namespace dawnforge::procgen
