#include <dawnforge/runtime/sky.hpp>

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>

namespace dawnforge::runtime {

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kNoonElevation = 55.0 * kPi / 180.0;

double smoothstep(double a, double b, double x) {
    const double t = std::clamp((x - a) / (b - a), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}
}  // namespace

Lighting lightingAt(double hours) {
    hours = std::fmod(hours, 24.0);
    if (hours < 0.0) hours += 24.0;
    Lighting L;
    const double phi = kPi * (hours - 6.0) / 12.0;  // 0 at sunrise (east), π at sunset (west)
    const double elevation = kNoonElevation * std::sin(phi);
    L.elevation = elevation;
    const double s = std::sin(elevation);
    const glm::dvec3 sun{std::cos(elevation) * std::cos(phi), s, std::cos(elevation) * std::sin(phi)};

    const double day = smoothstep(-0.04, 0.12, s);  // direct sunlight fades in after sunrise
    L.night = 1.0 - smoothstep(-0.12, 0.04, s);
    const double low = 1.0 - smoothstep(0.05, 0.45, s);  // warm light near the horizon
    const glm::dvec3 warm{1.0, 0.52, 0.26}, white{1.0, 0.96, 0.9};
    if (L.night < 1.0 && s > -0.04) {
        L.sunDirection = glm::normalize(glm::dvec3(sun.x, std::max(sun.y, 0.02), sun.z));
        L.sunColor = 3.2 * day * glm::mix(white, warm, low);
    } else {
        L.sunDirection = glm::normalize(glm::dvec3(-sun.x, 0.6, -sun.z + 0.3));  // the moon
        L.sunColor = glm::dvec3(0.05, 0.07, 0.12);
    }
    const glm::dvec3 dayZenith{0.22, 0.42, 0.85}, dayHorizon{0.68, 0.8, 0.95};
    const glm::dvec3 duskZenith{0.28, 0.26, 0.5}, duskHorizon{1.0, 0.55, 0.3};
    const glm::dvec3 nightZenith{0.008, 0.012, 0.035}, nightHorizon{0.02, 0.03, 0.06};
    L.zenith = glm::mix(glm::mix(dayZenith, duskZenith, low), nightZenith, L.night);
    L.horizon = glm::mix(glm::mix(dayHorizon, duskHorizon, low), nightHorizon, L.night);
    L.ground = glm::mix(glm::dvec3(0.3, 0.28, 0.25) * (0.4 + 0.6 * day), glm::dvec3(0.01, 0.012, 0.02), L.night);
    return L;
}

}  // namespace dawnforge::runtime
