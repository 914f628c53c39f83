// The bake's greyscale albedo: the luminance of core's mean colour of each material's tile (materials.hpp).
#include <dawnforge/bake/lighting.hpp>

#include <dawnforge/core/materials.hpp>

namespace dawnforge::bake {

std::array<float, 16> defaultAlbedo() {
    std::array<float, 16> a{};
    for (std::uint8_t m = 0; m < 16; ++m) {
        const glm::vec3 c = materialMeanColour(m);
        a[m] = 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b;
    }
    return a;
}

}  // namespace dawnforge::bake
