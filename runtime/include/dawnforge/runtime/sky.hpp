#pragma once
// Sun and sky from the time of day (hours), the same numbers the shaders get.
#include <glm/vec3.hpp>

namespace dawnforge::runtime {

struct Lighting {
    glm::dvec3 sunDirection{0, 1, 0};  // unit, towards the sun (or the moon at night)
    glm::dvec3 sunColor{1.0};          // linear radiance of the direct light
    glm::dvec3 zenith{0.3, 0.5, 0.9};  // sky colour straight up
    glm::dvec3 horizon{0.7, 0.8, 0.9}; // sky colour at the horizon
    glm::dvec3 ground{0.2};            // light bounced up from the ground
    double elevation = 0.0;            // of the sun, radians (negative at night)
    double night = 0.0;                // 0 by day, 1 at night: windows light up
};

// The sun rises in the east (+x) at 6:00, crosses the south (+z, glTF axes with the city's
// north at −z) at 12:00 at 55° and sets in the west at 18:00; at night a dim blue moon
// light comes from the opposite side. `hours` is wrapped into [0, 24).
Lighting lightingAt(double hours);

}  // namespace dawnforge::runtime
