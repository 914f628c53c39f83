// The plan's east-north-up frame on the WGS84 ellipsoid (plan.hpp).
#include <dawnforge/world/plan.hpp>

#include <cmath>

namespace dawnforge::world {

glm::dmat4 enuToEcef(const GeoOrigin& origin) {
    constexpr double kA = 6378137.0;            // WGS84 semi-major axis, m
    constexpr double kE2 = 6.69437999014e-3;    // first eccentricity squared
    constexpr double kDegree = 3.14159265358979323846 / 180.0;
    const double lon = origin.longitude * kDegree, lat = origin.latitude * kDegree;
    const double sinLon = std::sin(lon), cosLon = std::cos(lon), sinLat = std::sin(lat), cosLat = std::cos(lat);
    const double n = kA / std::sqrt(1.0 - kE2 * sinLat * sinLat);  // prime vertical radius of curvature
    glm::dmat4 m(1.0);
    m[0] = glm::dvec4(-sinLon, cosLon, 0.0, 0.0);                                  // east
    m[1] = glm::dvec4(-sinLat * cosLon, -sinLat * sinLon, cosLat, 0.0);            // north
    m[2] = glm::dvec4(cosLat * cosLon, cosLat * sinLon, sinLat, 0.0);              // up
    m[3] = glm::dvec4((n + origin.height) * cosLat * cosLon, (n + origin.height) * cosLat * sinLon,
                      (n * (1.0 - kE2) + origin.height) * sinLat, 1.0);
    return m;
}

}  // namespace dawnforge::world
