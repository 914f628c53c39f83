// Probe arithmetic against identities that do not depend on how it is written: constant
// radiance gives πL, a unit directional light gives 1.0625, 0.09375 and 0.0625 (the L2
// ringing of shared/notes/measured.md), cube texels cover 4π, octahedral maps round-trip,
// ambient-cube weights sum to 1, and Chebyshev visibility is 1 up to the mean.
#include <dawnforge/runtime/probe_math.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace dawnforge::runtime {
namespace {

constexpr double kPi = std::numbers::pi;

std::vector<glm::dvec3> randomDirections(int count, unsigned seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> g(0.0, 1.0);
    std::vector<glm::dvec3> out;
    while (int(out.size()) < count) {
        const glm::dvec3 v(g(rng), g(rng), g(rng));
        if (glm::length(v) > 1e-6) out.push_back(glm::normalize(v));
    }
    return out;
}

// A cube map whose every texel holds radiance(direction).
template <typename Radiance>
std::array<std::vector<glm::vec3>, 6> capture(int size, Radiance radiance) {
    std::array<std::vector<glm::vec3>, 6> faces;
    for (int f = 0; f < 6; ++f)
        for (int y = 0; y < size; ++y)
            for (int x = 0; x < size; ++x) faces[std::size_t(f)].push_back(glm::vec3(radiance(cubeTexelDirection(f, x, y, size))));
    return faces;
}

TEST(ProbeMath, ConstantRadianceGivesPiLForEveryNormal) {
    const glm::dvec3 l(0.3, 0.5, 0.9);
    const ShRgb sh = shProjectCube(capture(32, [&](glm::dvec3) { return l; }), 32);
    for (const glm::dvec3& n : randomDirections(500, 1)) {
        const glm::dvec3 e = shIrradiance(sh, n);
        EXPECT_NEAR(e.r, kPi * l.r, 1e-5);
        EXPECT_NEAR(e.g, kPi * l.g, 1e-5);
        EXPECT_NEAR(e.b, kPi * l.b, 1e-5);
        EXPECT_NEAR(ambientIrradiance(ambientCubeFromSh(sh), n).b, kPi * l.b, 1e-5);
    }
}

TEST(ProbeMath, AUnitDirectionalLightRingsAsL2Does) {
    for (const glm::dvec3& d : randomDirections(50, 2)) {
        const ShRgb sh = shDirectional(d, glm::dvec3(1.0));
        const glm::dvec3 side = glm::normalize(glm::cross(d, std::abs(d.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
        EXPECT_NEAR(shIrradiance(sh, d).r, 1.0625, 1e-9);
        EXPECT_NEAR(shIrradiance(sh, side).g, 0.09375, 1e-9);
        EXPECT_NEAR(shIrradiance(sh, -d).b, 0.0625, 1e-9);
    }
}

// A small bright patch captured in a cube map projects like a directional light of the same power.
TEST(ProbeMath, ACapturedSunProjectsLikeADirectionalLight) {
    const glm::dvec3 sun = glm::normalize(glm::dvec3(0.3, 0.8, -0.5));
    const int size = 64;
    double power = 0.0;
    auto faces = capture(size, [&](glm::dvec3 d) { return glm::dvec3(glm::dot(d, sun) > 0.995 ? 1.0 : 0.0); });
    for (int f = 0; f < 6; ++f)
        for (int y = 0; y < size; ++y)
            for (int x = 0; x < size; ++x) power += faces[std::size_t(f)][std::size_t(y * size + x)].r * cubeTexelSolidAngle(x, y, size);
    const ShRgb captured = shProjectCube(faces, size), delta = shDirectional(sun, glm::dvec3(power));
    for (const glm::dvec3& n : randomDirections(100, 3))
        EXPECT_NEAR(shIrradiance(captured, n).r, shIrradiance(delta, n).r, 0.01 * power);
}

TEST(ProbeMath, CubeTexelsCoverTheSphereOnceFromTheirOwnFace) {
    for (int size : {1, 5, 64}) {
        double total = 0.0;
        for (int f = 0; f < 6; ++f)
            for (int y = 0; y < size; ++y)
                for (int x = 0; x < size; ++x) {
                    total += cubeTexelSolidAngle(x, y, size);
                    const glm::dvec3 d = cubeTexelDirection(f, x, y, size);
                    const int axis = std::abs(d.x) >= std::max(std::abs(d.y), std::abs(d.z)) ? 0
                                     : std::abs(d.y) >= std::abs(d.z)                       ? 1
                                                                                            : 2;
                    EXPECT_EQ(2 * axis + (d[axis] < 0.0 ? 1 : 0), f) << "face " << f << " texel " << x << "," << y;
                }
        EXPECT_NEAR(total, 4.0 * kPi, 1e-12) << size;
    }
}

TEST(ProbeMath, OctahedralMapsRoundTrip) {
    for (const glm::dvec3& d : randomDirections(10000, 4)) {
        const glm::dvec2 e = octEncode(d);
        EXPECT_LE(std::abs(e.x), 1.0);
        EXPECT_LE(std::abs(e.y), 1.0);
        EXPECT_LT(glm::length(octDecode(e) - d), 1e-12);
    }
    for (const glm::dvec3& axis : {glm::dvec3(0, 1, 0), glm::dvec3(0, -1, 0), glm::dvec3(1, 0, 0), glm::dvec3(0, 0, -1)})
        EXPECT_LT(glm::length(octDecode(octEncode(axis)) - axis), 1e-15);
    EXPECT_LT(glm::length(octEncode({0, 1, 0})), 1e-15) << "+Y is the map's centre";
}

TEST(ProbeMath, AmbientCubeWeightsSumToOneAndHoldTheAxes) {
    const ShRgb sky = shDirectional(glm::normalize(glm::dvec3(0.2, 1.0, 0.1)), glm::dvec3(2.0, 1.5, 1.0));
    const AmbientCube cube = ambientCubeFromSh(sky);
    for (const glm::dvec3& n : randomDirections(1000, 5)) {
        const AmbientWeights w = ambientWeights(n);
        EXPECT_NEAR(w.weight[0] + w.weight[1] + w.weight[2], 1.0, 1e-12);
    }
    const glm::dvec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (const glm::dvec3& a : axes) EXPECT_LT(glm::length(ambientIrradiance(cube, a) - shIrradiance(sky, a)), 1e-12);
}

// The 5 × 5 octahedral texture holds the irradiance at its texel centres, and a bilinear
// sample between them stays within the range of its four texels.
TEST(ProbeMath, OctahedralIrradianceTextureHoldsTheIrradianceAtItsTexels) {
    const ShRgb sky = shDirectional(glm::normalize(glm::dvec3(0.2, 1.0, 0.1)), glm::dvec3(3.0));
    const int size = 5;
    const std::vector<glm::vec3> texels = octIrradianceTexture(sky, size);
    ASSERT_EQ(texels.size(), 25u);
    for (int j = 0; j < size; ++j)
        for (int i = 0; i < size; ++i) {
            const glm::dvec3 d = octDecode({2.0 * (i + 0.5) / size - 1.0, 2.0 * (j + 0.5) / size - 1.0});
            EXPECT_NEAR(sampleOctTexture(texels, size, d).r, shIrradiance(sky, d).r, 1e-5);
        }
    float lo = texels[0].r, hi = texels[0].r;
    for (const glm::vec3& t : texels) lo = std::min(lo, t.r), hi = std::max(hi, t.r);
    for (const glm::dvec3& n : randomDirections(500, 6)) {
        const double s = sampleOctTexture(texels, size, n).r;
        EXPECT_GE(s, lo - 1e-6);
        EXPECT_LE(s, hi + 1e-6);
    }
}

TEST(ProbeMath, ChebyshevIsOneUpToTheMeanAndFallsBeyondIt) {
    EXPECT_EQ(chebyshevVisibility(1.0, 2.0, 4.5), 1.0);
    EXPECT_EQ(chebyshevVisibility(2.0, 2.0, 4.5), 1.0);
    EXPECT_NEAR(chebyshevVisibility(3.0, 2.0, 4.5), 0.5 / (0.5 + 1.0), 1e-12);
    double previous = 1.0;
    for (double d = 2.1; d < 20.0; d += 0.5) {
        const double v = chebyshevVisibility(d, 2.0, 4.5);
        EXPECT_LT(v, previous);
        previous = v;
    }
    EXPECT_LT(previous, 0.002);
    EXPECT_LT(chebyshevVisibility(2.5, 2.0, 4.0), 1e-9) << "no spread: anything beyond the mean is hidden";
}

}  // namespace
}  // namespace dawnforge::runtime
