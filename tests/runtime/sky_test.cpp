#include <dawnforge/runtime/sky.hpp>

#include <gtest/gtest.h>

#include <glm/glm.hpp>

using namespace dawnforge::runtime;

TEST(Sky, SunRisesInTheEastCrossesTheSouthAndSetsInTheWest) {
    EXPECT_GT(lightingAt(12.0).sunDirection.y, 0.8);       // 55° at noon
    EXPECT_NEAR(lightingAt(12.0).sunDirection.z, std::cos(55.0 * 3.14159265358979 / 180.0), 1e-9);  // south is +z
    EXPECT_GT(lightingAt(8.0).sunDirection.x, 0.5);        // morning: east
    EXPECT_LT(lightingAt(16.0).sunDirection.x, -0.5);      // afternoon: west
    EXPECT_GT(lightingAt(12.0).elevation, 0.9);
    EXPECT_LT(lightingAt(0.0).elevation, -0.9);
    EXPECT_DOUBLE_EQ(lightingAt(26.0).elevation, lightingAt(2.0).elevation);  // hours wrap
    EXPECT_DOUBLE_EQ(lightingAt(-3.0).elevation, lightingAt(21.0).elevation);
}

TEST(Sky, NightIsDarkAndEveningIsWarm) {
    const Lighting noon = lightingAt(12.0), evening = lightingAt(17.5), night = lightingAt(23.0);
    EXPECT_EQ(noon.night, 0.0);
    EXPECT_EQ(night.night, 1.0);
    EXPECT_LT(glm::length(night.sunColor), 0.2 * glm::length(noon.sunColor));
    // Evening light is redder than noon light (blue/red ratio lower), the horizon warmer.
    EXPECT_LT(evening.sunColor.b / evening.sunColor.r, noon.sunColor.b / noon.sunColor.r - 0.2);
    EXPECT_GT(evening.horizon.r / evening.horizon.b, noon.horizon.r / noon.horizon.b);
    EXPECT_LT(glm::length(night.zenith), 0.1);
}

TEST(Sky, LightChangesContinuouslyThroughTheDay) {
    Lighting previous = lightingAt(0.0);
    for (int i = 1; i <= 24 * 60; ++i) {
        const Lighting l = lightingAt(i / 60.0);
        EXPECT_NEAR(glm::length(l.sunDirection), 1.0, 1e-9);
        EXPECT_LT(glm::length(l.zenith - previous.zenith), 0.05) << "at minute " << i;
        EXPECT_LT(glm::length(l.horizon - previous.horizon), 0.05) << "at minute " << i;
        previous = l;
    }
}
