#pragma once
// Plan and plane geometry shared by the chart packer and the proxies (private to bake).
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace dawnforge::bake {

inline double cross2(glm::dvec2 a, glm::dvec2 b) { return a.x * b.y - a.y * b.x; }

// Andrew's monotone chain; returns the hull counter-clockwise without repeating the first point.
inline std::vector<glm::dvec2> convexHull(std::vector<glm::dvec2> pts) {
    std::sort(pts.begin(), pts.end(), [](glm::dvec2 a, glm::dvec2 b) { return a.x != b.x ? a.x < b.x : a.y < b.y; });
    pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
    if (pts.size() < 3) return pts;
    std::vector<glm::dvec2> hull(2 * pts.size());
    std::size_t k = 0;
    for (const glm::dvec2& p : pts) {
        while (k >= 2 && cross2(hull[k - 1] - hull[k - 2], p - hull[k - 2]) <= 0.0) --k;
        hull[k++] = p;
    }
    for (std::size_t i = pts.size() - 1, lower = k + 1; i-- > 0;) {
        while (k >= lower && cross2(hull[k - 1] - hull[k - 2], pts[i] - hull[k - 2]) <= 0.0) --k;
        hull[k++] = pts[i];
    }
    hull.resize(k - 1);
    return hull;
}

// The angle (radians, in [-π/4, π/4)) of the minimum-area bounding rectangle's first axis;
// equal areas (to 1e-9) keep the smallest |angle|, so axis-aligned shapes stay aligned.
inline double minAreaRectAngle(const std::vector<glm::dvec2>& hull) {
    constexpr double kPi = 3.14159265358979323846;
    if (hull.size() < 3) return 0.0;
    double bestArea = INFINITY, bestAngle = 0.0;
    const auto consider = [&](double angle) {
        angle = std::remainder(angle, kPi / 2);  // a rectangle is the same turned by 90°
        if (angle >= kPi / 4) angle -= kPi / 2;
        const double c = std::cos(angle), s = std::sin(angle);
        glm::dvec2 lo(INFINITY), hi(-INFINITY);
        for (const glm::dvec2& p : hull) {
            const glm::dvec2 q(c * p.x + s * p.y, -s * p.x + c * p.y);
            lo = glm::min(lo, q), hi = glm::max(hi, q);
        }
        const double area = (hi.x - lo.x) * (hi.y - lo.y);
        if (area < bestArea * (1.0 - 1e-9) || (area <= bestArea * (1.0 + 1e-9) && std::abs(angle) < std::abs(bestAngle))) {
            bestArea = std::min(bestArea, area);
            bestAngle = angle;
        }
    };
    consider(0.0);
    for (std::size_t i = 0; i < hull.size(); ++i) {
        const glm::dvec2 e = hull[(i + 1) % hull.size()] - hull[i];
        if (glm::length(e) > 1e-12) consider(std::atan2(e.y, e.x));
    }
    return bestAngle;
}

}  // namespace dawnforge::bake
