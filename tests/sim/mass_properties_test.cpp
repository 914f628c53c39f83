#include <dawnforge/core/primitives.hpp>
#include <dawnforge/sim/mass_properties.hpp>

#include <gtest/gtest.h>

#include <numbers>

using namespace dawnforge;
using namespace dawnforge::sim;

namespace {

MassProperties of(const Mesh& m, double density) {
    const std::vector<glm::dvec3> p(m.positions.begin(), m.positions.end());
    return computeMassProperties(p, m.indices, density);
}

}  // namespace

TEST(MassProperties, BoxMatchesTheClosedForm) {
    // A 1 × 2 × 3 box at (5, 6, 7): I_xx = m (b² + c²) / 12, and so on; products of inertia 0.
    const MassProperties mp = of(makeBox({5, 6, 7}, {6, 8, 10}), 10.0);
    EXPECT_NEAR(mp.volume, 6.0, 1e-12);
    EXPECT_NEAR(mp.mass, 60.0, 1e-10);
    EXPECT_NEAR(glm::distance(mp.centerOfMass, glm::dvec3(5.5, 7.0, 8.5)), 0.0, 1e-12);
    EXPECT_NEAR(mp.inertia[0][0], 60.0 * (4 + 9) / 12.0, 1e-9);
    EXPECT_NEAR(mp.inertia[1][1], 60.0 * (1 + 9) / 12.0, 1e-9);
    EXPECT_NEAR(mp.inertia[2][2], 60.0 * (1 + 4) / 12.0, 1e-9);
    EXPECT_NEAR(mp.inertia[0][1], 0.0, 1e-9);
    EXPECT_NEAR(mp.inertia[1][2], 0.0, 1e-9);
    EXPECT_NEAR(mp.inertia[0][2], 0.0, 1e-9);
}

TEST(MassProperties, SphereApproachesTwoFifthsMR2) {
    const MassProperties mp = of(makeIcosphere(2.0f, 5), 1.0);
    const double expected = 0.4 * mp.mass * 4.0;
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(mp.inertia[k][k] / expected, 1.0, 2e-3);
    EXPECT_NEAR(mp.volume / (4.0 / 3.0 * std::numbers::pi * 8.0), 1.0, 3e-3);
    EXPECT_NEAR(glm::length(mp.centerOfMass), 0.0, 1e-6);
}

TEST(MassProperties, RotatedBoxHasProductsOfInertia) {
    // A long box along the diagonal x = y: the product of inertia I_xy must be negative
    // (mass where x and y have the same sign) and the tensor symmetric.
    Mesh box = makeBox({-2, -0.1f, -0.1f}, {2, 0.1f, 0.1f});
    for (glm::vec3& p : box.positions) p = glm::vec3((p.x - p.y) * 0.70710678f, (p.x + p.y) * 0.70710678f, p.z);
    const MassProperties mp = of(box, 1.0);
    EXPECT_LT(mp.inertia[0][1], -0.1);
    EXPECT_DOUBLE_EQ(mp.inertia[0][1], mp.inertia[1][0]);
    EXPECT_NEAR(mp.inertia[0][0], mp.inertia[1][1], 1e-6);
}
