// Material colours for the bake: the mean linear colour of each material's block in the
// runtime's procedural atlas (runtime/src/atlas.cpp; brick and plaster: the mean of their four
// variants). tests/runtime/atlas_test.cpp recomputes them from the atlas and holds them to 0.005.
#include <dawnforge/bake/lighting.hpp>

#include <dawnforge/core/error.hpp>

namespace dawnforge::bake {

namespace {
constexpr glm::vec3 kColours[16] = {
    {0.0497f, 0.0497f, 0.0539f},  // asphalt
    {0.4430f, 0.3512f, 0.2610f},  // paving
    {0.3063f, 0.2062f, 0.1484f},  // brick
    {0.3267f, 0.3267f, 0.3036f},  // concrete
    {0.5860f, 0.4653f, 0.3653f},  // plaster
    {0.0193f, 0.0325f, 0.0540f},  // glass
    {0.1019f, 0.1215f, 0.1510f},  // metal
    {0.5807f, 0.5169f, 0.3760f},  // trim
    {0.3203f, 0.0647f, 0.0277f},  // roof tiles
    {0.2039f, 0.1735f, 0.1391f},  // flat roof
    {0.2040f, 0.0849f, 0.0287f},  // wood
    {0.7874f, 0.7677f, 0.7105f},  // interior wall
    {0.3395f, 0.2691f, 0.1848f},  // floor
    {0.0795f, 0.1429f, 0.0275f},  // ground
    {0.6025f, 0.4759f, 0.2627f},  // sand
    {0.2652f, 0.2235f, 0.1833f},  // rubble
};
}  // namespace

glm::vec3 materialColour(std::uint8_t material) {
    DAWNFORGE_ASSERT(material < 16, "materialColour(): material IDs are 0..15");
    return kColours[material];
}

std::array<float, 16> defaultAlbedo() {
    std::array<float, 16> a{};
    for (std::size_t m = 0; m < 16; ++m) a[m] = 0.2126f * kColours[m].r + 0.7152f * kColours[m].g + 0.0722f * kColours[m].b;
    return a;
}

}  // namespace dawnforge::bake
