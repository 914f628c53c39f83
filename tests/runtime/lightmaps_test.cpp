// Placing the receivers' lightmaps in the layers of one texture array (lightmaps.hpp).
#include <dawnforge/runtime/lightmaps.hpp>

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace dawnforge::runtime {
namespace {

TEST(Lightmaps, PlacementKeepsEveryAtlasWholeApartAndOnEvenTexels) {
    std::vector<glm::ivec2> sizes;
    std::vector<std::string> names;
    for (int i = 0; i < 90; ++i) {
        sizes.emplace_back(2 * (20 + (i * 37) % 300), 2 * (10 + (i * 53) % 260));
        names.push_back("building_" + std::to_string(i));
    }
    sizes.emplace_back(2048, 1024);  // one as wide as a layer
    names.push_back("ground_0_0");
    const LightmapPlacement p = placeLightmaps(sizes, names);
    EXPECT_EQ(p.layerSize, 2048);
    ASSERT_GE(p.layers, 2);
    std::vector<std::vector<std::uint8_t>> used(std::size_t(p.layers), std::vector<std::uint8_t>(2048u * 2048u, 0));
    for (std::size_t i = 0; i < sizes.size(); ++i) {
        const glm::ivec3 at = p.placed[i];
        EXPECT_EQ(at.x % 2, 0);
        EXPECT_EQ(at.y % 2, 0);
        ASSERT_LE(at.x + sizes[i].x, p.layerSize);
        ASSERT_LE(at.y + sizes[i].y, p.layerSize);
        ASSERT_LT(at.z, p.layers);
        for (int y = at.y; y < at.y + sizes[i].y; ++y)
            for (int x = at.x; x < at.x + sizes[i].x; ++x) {
                std::uint8_t& u = used[std::size_t(at.z)][std::size_t(y) * 2048u + std::size_t(x)];
                ASSERT_EQ(u, 0) << "atlases overlap at " << x << ", " << y;
                u = 1;
            }
    }
    // A small city fits one small layer.
    const std::vector<glm::ivec2> small{{100, 60}, {40, 40}};
    const std::vector<std::string> smallNames{"a", "b"};
    const LightmapPlacement q = placeLightmaps(small, smallNames);
    EXPECT_EQ(q.layers, 1);
    EXPECT_EQ(q.layerSize, 256);
}

}  // namespace
}  // namespace dawnforge::runtime
