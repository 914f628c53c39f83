// Properties of the ocean: Gerstner waves with Σ Q·k·A ≤ 1 never fold (and do above it),
// crests move at the deep-water phase speed, normals match the displaced surface, the
// buoyancy query inverts the horizontal displacement, the noise texture samples like GL,
// and the projected grid stays on the water and inside the view for many cameras.
#include <dawnforge/runtime/ocean.hpp>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <vector>

using namespace dawnforge::runtime;

namespace {

constexpr double kPi = std::numbers::pi;

// A small deterministic generator for test inputs (SplitMix64).
class TestRng {
public:
    explicit TestRng(std::uint64_t seed) : state_(seed) {}
    double uniform(double lo, double hi) {
        state_ += 0x9E3779B97F4A7C15ull;
        std::uint64_t z = state_;
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        z ^= z >> 31;
        return lo + (hi - lo) * static_cast<double>(z >> 11) * 0x1.0p-53;
    }

private:
    std::uint64_t state_;
};

// Random waves within a cone of directions around a random wind (a narrow cone is the
// hardest case for folding: the waves' horizontal motions add up).
WaveSet randomWaves(TestRng& rng, double coneHalfWidth) {
    WaveSet set;
    const double wind = rng.uniform(-kPi, kPi);
    for (GerstnerWave& w : set.waves) {
        const double angle = wind + rng.uniform(-coneHalfWidth, coneHalfWidth);
        w.direction = {std::cos(angle), std::sin(angle)};
        w.wavelength = std::exp(rng.uniform(std::log(5.0), std::log(80.0)));
        w.amplitude = rng.uniform(0.05, 1.0);
        w.steepness = rng.uniform(0.1, 1.0);
        w.phase = rng.uniform(0.0, 2.0 * kPi);
    }
    return set;
}

// The smallest horizontal Jacobian over a dense grid of space (120 m square, 0.75 m steps,
// finer than a quarter of the shortest wavelength) and time.
double minJacobian(const WaveSet& set, double attenuation = 1.0) {
    double lowest = std::numeric_limits<double>::infinity();
    for (int ti = 0; ti < 8; ++ti) {
        const double t = 0.37 + 1.91 * ti;
        for (int i = 0; i <= 160; ++i)
            for (int j = 0; j <= 160; ++j)
                lowest = std::min(lowest, gerstner(set, {-60.0 + 0.75 * i, -60.0 + 0.75 * j}, t, attenuation).jacobian);
    }
    return lowest;
}

glm::dvec3 surfacePoint(const WaveSet& set, glm::dvec2 x0, double t, double attenuation) {
    return glm::dvec3(x0.x, 0.0, x0.y) + gerstner(set, x0, t, attenuation).displacement;
}

double deg(double degrees) { return degrees * kPi / 180.0; }

OceanCamera makeCamera(glm::dvec3 position, double pitchDeg, double yawDeg, double fovDeg, double aspect) {
    OceanCamera c;
    c.position = position;
    const double p = deg(pitchDeg), y = deg(yawDeg);
    c.forward = {std::cos(p) * std::sin(y), std::sin(p), -std::cos(p) * std::cos(y)};
    c.fovYRadians = deg(fovDeg);
    c.aspect = aspect;
    c.nearPlane = 0.02;  // below the lowest test camera's nearest water
    c.farPlane = 5000.0;
    return c;
}

glm::dvec3 horizontalHeading(const OceanCamera& c) {
    return glm::normalize(glm::dvec3(c.forward.x, 0.0, c.forward.z));
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Folding

TEST(OceanWaves, DefaultWavesDoNotFold) {
    const WaveSet set = defaultWaves();
    const double f = foldFactor(set);
    EXPECT_LE(f, 1.0);
    EXPECT_NEAR(f, 0.8, 1e-12);
    for (const GerstnerWave& w : set.waves) {
        EXPECT_NEAR(glm::length(w.direction), 1.0, 1e-12);
        EXPECT_GE(w.wavelength, 8.0);
        EXPECT_LE(w.wavelength, 60.0);
    }
    // The eigenvalues of I − Σ Q A k sinθ D Dᵀ lie in [1 − f, 1 + f], so J ≥ (1 − f)².
    const double lowest = minJacobian(set);
    EXPECT_GT(lowest, 0.0);
    EXPECT_GE(lowest, (1.0 - f) * (1.0 - f) - 1e-12);
    EXPECT_GT(minJacobian(set, 0.4), lowest);  // shore attenuation only makes it safer
}

TEST(OceanWaves, FoldFactorOneNeverFolds) {
    TestRng rng(42);
    for (int i = 0; i < 12; ++i) {
        const double cone = i % 3 == 0 ? deg(5.0) : i % 3 == 1 ? deg(45.0) : kPi;
        const WaveSet base = randomWaves(rng, cone);
        const WaveSet atOne = withFoldFactor(base, 1.0);
        ASSERT_NEAR(foldFactor(atOne), 1.0, 1e-12);
        // J ≥ 0 exactly; allow the rounding of a sum of four products.
        EXPECT_GE(minJacobian(atOne), -1e-12) << "set " << i;
        const WaveSet below = withFoldFactor(base, 0.999);
        const double lowest = minJacobian(below);
        EXPECT_GT(lowest, 0.0) << "set " << i;
        EXPECT_GE(lowest, 0.001 * 0.001 - 1e-12) << "set " << i;
    }
}

TEST(OceanWaves, FoldFactorAboveOneFolds) {
    // One wave at Q k A = 1.5: J = 1 − 1.5 sin θ < 0 under the crest.
    WaveSet single;
    single.waves[0] = {{0.6, 0.8}, 0.5, 20.0, 1.0, 0.3};
    for (std::size_t i = 1; i < 4; ++i) single.waves[i].amplitude = 0.0;
    EXPECT_LT(minJacobian(withFoldFactor(single, 1.5)), -0.25);

    // The default waves turned to within ±10° of the wind and steepened to 1.5.
    WaveSet narrow = defaultWaves();
    const double spread[4] = {0.0, 10.0, -7.0, 4.0};
    for (std::size_t i = 0; i < 4; ++i) narrow.waves[i].direction = {std::cos(deg(spread[i])), std::sin(deg(spread[i]))};
    EXPECT_LT(minJacobian(withFoldFactor(narrow, 1.5)), 0.0);
}

// ---------------------------------------------------------------------------------------
// Motion and shape

TEST(OceanWaves, CrestTravelsOneWavelengthPerPeriod) {
    const glm::dvec2 d{0.6, 0.8};
    const double wavelength = 20.0;
    WaveSet set;
    set.waves[0] = {d, 0.5, wavelength, 0.9, 0.3};
    for (std::size_t i = 1; i < 4; ++i) set.waves[i].amplitude = 0.0;
    const double k = 2.0 * kPi / wavelength;
    const double period = 2.0 * kPi / std::sqrt(9.81 * k);

    // The crest along the line s·D: where the displaced surface's slope along D changes
    // from rising to falling (the normal tilts from −D to +D), found by bisection.
    const auto slope = [&](double s, double t) {
        const glm::dvec3 n = gerstner(set, s * d, t).normal;
        return n.x * d.x + n.z * d.y;  // < 0 while rising, > 0 after the crest
    };
    const auto crestNear = [&](double guess, double t) {
        double lo = guess - wavelength / 4.0, hi = guess + wavelength / 4.0;
        EXPECT_LT(slope(lo, t), 0.0);
        EXPECT_GT(slope(hi, t), 0.0);
        for (int i = 0; i < 200; ++i) {
            const double mid = 0.5 * (lo + hi);
            (slope(mid, t) < 0.0 ? lo : hi) = mid;
        }
        const double s = 0.5 * (lo + hi);
        const glm::dvec3 p = surfacePoint(set, s * d, t, 1.0);
        return glm::dot(glm::dvec2(p.x, p.z), d);  // the displaced crest's position along D
    };

    // Start at a crest found by sampling the height along the line.
    double best = 0.0, bestHeight = -1.0;
    for (int i = 0; i < 400; ++i) {
        const double s = wavelength * i / 400.0;
        const double h = gerstner(set, s * d, 0.0).displacement.y;
        if (h > bestHeight) bestHeight = h, best = s;
    }
    const double start = crestNear(best, 0.0);
    EXPECT_NEAR(bestHeight, 0.5, 1e-3);

    double crest = start;
    const int steps = 100;
    for (int i = 1; i <= steps; ++i) {
        const double t = period * i / steps;
        const double next = crestNear(crest, t);
        EXPECT_GT(next, crest);  // moves along +D, by a small step each time
        EXPECT_LT(next - crest, wavelength / 10.0);
        crest = next;
        if (i == steps / 2) {
            EXPECT_NEAR(crest - start, wavelength / 2.0, 1e-6);
        }
    }
    EXPECT_NEAR(crest - start, wavelength, 1e-6);
}

TEST(OceanWaves, NormalMatchesFiniteDifferences) {
    TestRng rng(7);
    std::vector<WaveSet> sets{defaultWaves()};
    for (int i = 0; i < 4; ++i) sets.push_back(withFoldFactor(randomWaves(rng, kPi), 0.9));
    const double h = 1e-4;
    for (const WaveSet& set : sets) {
        for (int i = 0; i < 200; ++i) {
            const glm::dvec2 x0{rng.uniform(-100.0, 100.0), rng.uniform(-100.0, 100.0)};
            const double t = rng.uniform(0.0, 60.0), attenuation = rng.uniform(0.2, 1.0);
            const WaveSample s = gerstner(set, x0, t, attenuation);
            EXPECT_NEAR(glm::length(s.normal), 1.0, 1e-12);
            const glm::dvec3 dx =
                (surfacePoint(set, x0 + glm::dvec2(h, 0), t, attenuation) - surfacePoint(set, x0 - glm::dvec2(h, 0), t, attenuation)) / (2 * h);
            const glm::dvec3 dz =
                (surfacePoint(set, x0 + glm::dvec2(0, h), t, attenuation) - surfacePoint(set, x0 - glm::dvec2(0, h), t, attenuation)) / (2 * h);
            const glm::dvec3 numeric = glm::normalize(glm::cross(dz, dx));
            EXPECT_LT(glm::length(numeric - s.normal), 1e-5);
            EXPECT_GT(s.normal.y, 0.0);
            // The Jacobian is the same determinant, taken numerically.
            EXPECT_NEAR(s.jacobian, dx.x * dz.z - dz.x * dx.z, 1e-6);
        }
    }
}

TEST(OceanWaves, AttenuationScalesTheWaves) {
    const WaveSet set = defaultWaves();
    const glm::dvec2 x0{12.5, -3.25};
    const WaveSample full = gerstner(set, x0, 4.0, 1.0), half = gerstner(set, x0, 4.0, 0.5);
    EXPECT_LT(glm::length(half.displacement - 0.5 * full.displacement), 1e-12);
    const WaveSample calm = gerstner(set, x0, 4.0, 0.0);
    EXPECT_EQ(calm.displacement, glm::dvec3(0.0));
    EXPECT_EQ(calm.normal, glm::dvec3(0.0, 1.0, 0.0));
    EXPECT_EQ(calm.jacobian, 1.0);
}

// ---------------------------------------------------------------------------------------
// Buoyancy

TEST(OceanWaves, WaterSurfaceAtFindsThePointAbove) {
    const WaveNoise noise = makeWaveNoise(64, 3);
    TestRng rng(11);
    std::vector<WaveSet> sets{defaultWaves()};
    for (int i = 0; i < 3; ++i) sets.push_back(withFoldFactor(randomWaves(rng, deg(20.0)), 0.95));
    for (const WaveSet& set : sets) {
        for (int i = 0; i < 300; ++i) {
            const glm::dvec2 xz{rng.uniform(-500.0, 500.0), rng.uniform(-500.0, 500.0)};
            const double t = rng.uniform(0.0, 300.0), attenuation = rng.uniform(0.0, 1.0), level = rng.uniform(-5.0, 5.0);
            const SurfacePoint s = waterSurfaceAt(set, noise, level, xz, t, attenuation);
            const WaveSample g = gerstner(set, s.x0, t, attenuation);
            const glm::dvec2 landed = s.x0 + glm::dvec2(g.displacement.x, g.displacement.z);
            EXPECT_LT(glm::length(landed - xz), 1e-6);
            EXPECT_NEAR(s.height, level + g.displacement.y + noiseHeight(set, noise, s.x0, t, attenuation), 1e-12);
            EXPECT_LT(glm::length(s.normal - g.normal), 1e-12);
        }
    }
}

// ---------------------------------------------------------------------------------------
// Noise texture

TEST(OceanNoise, DeterministicTileableAndInRange) {
    const WaveNoise a = makeWaveNoise(64, 5), b = makeWaveNoise(64, 5), c = makeWaveNoise(64, 6);
    ASSERT_EQ(a.size, 64);
    ASSERT_EQ(a.rgba.size(), 64u * 64u * 4u);
    EXPECT_EQ(a.rgba, b.rgba);
    EXPECT_NE(a.rgba, c.rgba);
    for (int ch = 0; ch < 4; ++ch) {
        float lo = 1.0f, hi = 0.0f;
        for (std::size_t p = 0; p < 64 * 64; ++p) {
            lo = std::min(lo, a.rgba[p * 4 + ch]);
            hi = std::max(hi, a.rgba[p * 4 + ch]);
        }
        EXPECT_EQ(lo, 0.0f);
        EXPECT_EQ(hi, 1.0f);
    }
    // Tileable: the step across the wrap is no larger than steps inside the texture.
    for (int ch = 0; ch < 4; ++ch) {
        double inside = 0.0, across = 0.0;
        for (int j = 0; j < 64; ++j) {
            for (int i = 0; i + 1 < 64; ++i)
                inside = std::max(inside, std::abs(double(a.rgba[(j * 64 + i + 1) * 4 + ch]) - a.rgba[(j * 64 + i) * 4 + ch]));
            across = std::max(across, std::abs(double(a.rgba[(j * 64 + 0) * 4 + ch]) - a.rgba[(j * 64 + 63) * 4 + ch]));
            across = std::max(across, std::abs(double(a.rgba[(0 * 64 + j) * 4 + ch]) - a.rgba[(63 * 64 + j) * 4 + ch]));
        }
        EXPECT_LE(across, inside * 1.5) << "channel " << ch;
        EXPECT_LT(inside, 0.3) << "channel " << ch;  // smooth: neighbouring texels are close
    }
}

TEST(OceanNoise, SamplesLikeGlLinearRepeat) {
    const WaveNoise noise = makeWaveNoise(32, 9);
    const int n = noise.size;
    const auto texel = [&](int i, int j, int ch) { return double(noise.rgba[(j * n + i) * 4 + ch]); };
    TestRng rng(3);
    for (int ch = 0; ch < 4; ++ch) {
        for (int j = 0; j < n; ++j) {
            for (int i = 0; i < n; ++i) {
                const glm::dvec2 centre{(i + 0.5) / n, (j + 0.5) / n};
                EXPECT_NEAR(sampleNoise(noise, centre, ch), texel(i, j, ch), 1e-12);
                // Midpoints between centres (wrapping) average their texels.
                const int i1 = (i + 1) % n, j1 = (j + 1) % n;
                EXPECT_NEAR(sampleNoise(noise, centre + glm::dvec2(0.5 / n, 0.0), ch), 0.5 * (texel(i, j, ch) + texel(i1, j, ch)), 1e-12);
                EXPECT_NEAR(sampleNoise(noise, centre + glm::dvec2(0.0, 0.5 / n), ch), 0.5 * (texel(i, j, ch) + texel(i, j1, ch)), 1e-12);
                EXPECT_NEAR(sampleNoise(noise, centre + glm::dvec2(0.5 / n, 0.5 / n), ch),
                            0.25 * (texel(i, j, ch) + texel(i1, j, ch) + texel(i, j1, ch) + texel(i1, j1, ch)), 1e-12);
            }
        }
        for (int k = 0; k < 200; ++k) {
            const glm::dvec2 uv{rng.uniform(-3.0, 3.0), rng.uniform(-3.0, 3.0)};
            const double v = sampleNoise(noise, uv, ch);
            EXPECT_NEAR(sampleNoise(noise, uv + glm::dvec2(1.0, 0.0), ch), v, 1e-9);
            EXPECT_NEAR(sampleNoise(noise, uv + glm::dvec2(0.0, 1.0), ch), v, 1e-9);
            EXPECT_NEAR(sampleNoise(noise, uv - glm::dvec2(2.0, 5.0), ch), v, 1e-9);
            EXPECT_GE(v, 0.0);
            EXPECT_LE(v, 1.0);
        }
    }
}

TEST(OceanNoise, NoiseHeightIsBoundedAndAttenuated) {
    const WaveSet set = defaultWaves();
    const WaveNoise noise = makeWaveNoise();
    TestRng rng(19);
    double lo = 0.0, hi = 0.0;
    for (int i = 0; i < 2000; ++i) {
        const glm::dvec2 x0{rng.uniform(-300.0, 300.0), rng.uniform(-300.0, 300.0)};
        const double t = rng.uniform(0.0, 100.0);
        const double h = noiseHeight(set, noise, x0, t);
        // Each (sample − 0.5) is within ±0.5 and the weights sum to 1.
        EXPECT_LE(std::abs(h), 0.5 * set.noiseAmplitude + 1e-12);
        EXPECT_NEAR(noiseHeight(set, noise, x0, t, 0.25), 0.25 * h, 1e-15);
        lo = std::min(lo, h);
        hi = std::max(hi, h);
    }
    EXPECT_GT(hi - lo, 0.2 * set.noiseAmplitude);  // it is not flat
}

// ---------------------------------------------------------------------------------------
// Projected grid

TEST(OceanGrid, VerticesLieOnTheWaterInsideTheView) {
    const double heights[] = {0.05, 1.0, 3.0, 10.0, 50.0, 200.0};
    const double pitches[] = {-1.0, -5.0, -15.0, -30.0, -45.0, -60.0, -75.0, -89.0};
    const double yaws[] = {0.0, 37.0, 145.0, 260.0};
    const double fovs[] = {30.0, 60.0, 90.0};
    const double aspects[] = {1.0, 1.78, 2.4};
    const double levels[] = {0.0, -3.5, 12.0};
    const int columns = 17, rows = 33;
    int cameras = 0;
    for (double height : heights)
    for (double pitch : pitches)
    for (double yaw : yaws)
    for (double fov : fovs)
    for (double aspect : aspects)
    for (double level : levels) {
        const OceanCamera cam = makeCamera({31.0, level + height, -17.0}, pitch, yaw, fov, aspect);
        const OceanGrid grid = projectOceanGrid(cam, level, columns, rows);
        const std::string where = "height " + std::to_string(height) + " pitch " + std::to_string(pitch) + " yaw " +
                                  std::to_string(yaw) + " fov " + std::to_string(fov) + " aspect " + std::to_string(aspect);
        // Every one of these cameras looks down at the water.
        ASSERT_TRUE(grid.visible) << where;
        ASSERT_EQ(grid.rowNdcY.size(), std::size_t(rows));
        ++cameras;
        const glm::dmat4 view = cam.view(), viewProjection = cam.projection() * view;
        const glm::dvec3 heading = horizontalHeading(cam);
        const bool bottomEdgeAhead = pitch - fov / 2.0 > -90.0;

        // The horizon's NDC y: a far point straight ahead on the level of the camera.
        const glm::dvec4 horizon = viewProjection * glm::dvec4(cam.position + heading * 1e9, 1.0);
        const double horizonY = horizon.y / horizon.w;
        EXPECT_LT(grid.rowNdcY.back(), horizonY) << where;
        // The first row is the bottom edge or the near plane; the last the top edge or the farthest allowed.
        EXPECT_TRUE(grid.rowNdcY.front() == -1.0 || std::abs(grid.rowDepth.front() / cam.nearPlane - 1.0) < 1e-6) << where;
        EXPECT_TRUE(grid.rowNdcY.back() > 1.0 - 1e-9 || std::abs(grid.rowDepth.back() - 2000.0) < 1e-9) << where;

        std::vector<double> previousDistance(columns, -1e300), previousAlong(columns, -1e300), previousDepth(columns, 0.0);
        for (int r = 0; r < rows; ++r) {
            if (r > 0) {
                EXPECT_GT(grid.rowNdcY[r], grid.rowNdcY[r - 1]) << where;
            }
            for (int c = 0; c < columns; ++c) {
                const glm::dvec3 p = oceanGridVertex(grid, c, r);
                const glm::dvec3 toVertex = p - cam.position;
                const double scale = std::max(1.0, glm::length(toVertex));
                EXPECT_LT(std::abs(p.y - level), 1e-6 * scale) << where;
                const glm::dvec4 clip = viewProjection * glm::dvec4(p, 1.0);
                ASSERT_GT(clip.w, 0.0) << where;  // in front of the camera
                const glm::dvec3 ndc = glm::dvec3(clip) / clip.w;
                EXPECT_LE(std::abs(ndc.x), 1.0 + 1e-6) << where;
                EXPECT_LE(std::abs(ndc.y), 1.0 + 1e-6) << where;
                EXPECT_LE(std::abs(ndc.z), 1.0 + 1e-6) << where;
                EXPECT_NEAR(ndc.x, -1.0 + 2.0 * c / (columns - 1), 1e-6) << where;
                EXPECT_NEAR(ndc.y, grid.rowNdcY[r], 1e-6) << where;
                const double depth = -(view * glm::dvec4(p, 1.0)).z;
                EXPECT_GE(depth, cam.nearPlane * (1.0 - 1e-6)) << where;
                EXPECT_LE(depth, cam.farPlane * (1.0 + 1e-6)) << where;
                EXPECT_NEAR(depth / grid.rowDepth[r], 1.0, 1e-6) << where;
                // Farther with every row: in depth, along the heading, and (when the screen's
                // bottom edge looks ahead of the point below the camera) in straight distance.
                const double along = glm::dot(toVertex, heading), distance = glm::length(toVertex);
                if (r > 0) {
                    EXPECT_GT(depth, previousDepth[c]) << where;
                    EXPECT_GT(along, previousAlong[c]) << where;
                    if (bottomEdgeAhead) {
                        EXPECT_GT(distance, previousDistance[c]) << where;
                    }
                }
                previousDepth[c] = depth;
                previousAlong[c] = along;
                previousDistance[c] = distance;
            }
        }
    }
    EXPECT_EQ(cameras, 6 * 8 * 4 * 3 * 3 * 3);
}

TEST(OceanGrid, InvisibleWhenNoWaterIsInView) {
    const double level = 4.0;
    // Below the water, at the water, looking up so that even the bottom edge is above the horizon.
    EXPECT_FALSE(projectOceanGrid(makeCamera({0, level - 1.0, 0}, -30.0, 0, 60.0, 1.5), level, 8, 8).visible);
    EXPECT_FALSE(projectOceanGrid(makeCamera({0, level, 0}, -30.0, 0, 60.0, 1.5), level, 8, 8).visible);
    EXPECT_FALSE(projectOceanGrid(makeCamera({0, level + 10.0, 0}, 40.0, 0, 60.0, 1.5), level, 8, 8).visible);
    EXPECT_FALSE(projectOceanGrid(makeCamera({0, level + 10.0, 0}, 80.0, 0, 90.0, 1.5), level, 8, 8).visible);
    // All the water in view is nearer than the near plane.
    OceanCamera low = makeCamera({0, level + 0.05, 0}, -45.0, 0, 30.0, 1.5);
    low.nearPlane = 0.1;
    EXPECT_FALSE(projectOceanGrid(low, level, 8, 8).visible);
    // All the water in view is beyond maxDistance.
    EXPECT_FALSE(projectOceanGrid(makeCamera({0, level + 100.0, 0}, -5.0, 0, 30.0, 1.5), level, 8, 8, 50.0).visible);
    // Looking slightly up, the bottom of the screen still sees water.
    EXPECT_TRUE(projectOceanGrid(makeCamera({0, level + 10.0, 0}, 5.0, 0, 60.0, 1.5), level, 8, 8).visible);
}

TEST(OceanGrid, RowsAreSpacedGeometrically) {
    const OceanCamera cam = makeCamera({0, 10.0, 0}, -30.0, 20.0, 60.0, 16.0 / 9.0);
    const OceanGrid grid = projectOceanGrid(cam, 0.0, 33, 160);
    ASSERT_TRUE(grid.visible);
    const glm::dvec3 heading = horizontalHeading(cam);
    std::vector<double> along;
    for (int r = 0; r < grid.rows; ++r) along.push_back(glm::dot(oceanGridVertex(grid, 16, r) - cam.position, heading));
    for (int r = 2; r < grid.rows; ++r) {
        const double gap = along[r] - along[r - 1], previous = along[r - 1] - along[r - 2];
        EXPECT_GT(gap, previous);
        // Geometric: the same ratio of depths from row to row.
        EXPECT_NEAR(grid.rowDepth[r] / grid.rowDepth[r - 1], grid.rowDepth[1] / grid.rowDepth[0], 1e-9);
    }
    // Near-field detail: the first rows are less than half a metre apart on the water.
    EXPECT_LT(glm::length(oceanGridVertex(grid, 16, 1) - oceanGridVertex(grid, 16, 0)), 0.5);
    // The far row reaches maxDistance (the top edge is at the horizon here).
    EXPECT_NEAR(grid.rowDepth.back(), 2000.0, 1e-9);
    // Around 200 m, far denser than screen-uniform rows (0.06 vertices per metre there).
    const auto rowAt = std::lower_bound(along.begin(), along.end(), 200.0) - along.begin();
    ASSERT_GT(rowAt, 0);
    EXPECT_GT(1.0 / (along[rowAt] - along[rowAt - 1]), 0.12);
}

TEST(OceanGrid, VirtualCameraKeepsGrazingRowsSpread) {
    // A camera 5 cm above the water, looking 1° down.
    const OceanCamera cam = makeCamera({0, 0.05, 0}, -1.0, 0.0, 60.0, 16.0 / 9.0);
    const OceanGrid withVirtual = projectOceanGrid(cam, 0.0, 9, 160, 2000.0, 2.0);
    const OceanGrid without = projectOceanGrid(cam, 0.0, 9, 160, 2000.0, 0.0);
    ASSERT_TRUE(withVirtual.visible);
    ASSERT_TRUE(without.visible);
    const auto rowsWithin = [](const OceanGrid& g, double depth) {
        return std::count_if(g.rowDepth.begin(), g.rowDepth.end(), [&](double d) { return d < depth; });
    };
    // Without it, a quarter of the rows would be spent on the first metre.
    EXPECT_GT(rowsWithin(without, 1.0), 30);
    EXPECT_LT(rowsWithin(withVirtual, 1.0), 12);
    // Same coverage: bottom edge to maxDistance.
    EXPECT_EQ(withVirtual.rowNdcY.front(), -1.0);
    EXPECT_NEAR(withVirtual.rowDepth.back(), 2000.0, 1e-9);
    // A camera above minHeight is not affected by it.
    const OceanCamera high = makeCamera({0, 10.0, 0}, -20.0, 0.0, 60.0, 1.5);
    EXPECT_EQ(projectOceanGrid(high, 0.0, 9, 40, 2000.0, 2.0).rowNdcY, projectOceanGrid(high, 0.0, 9, 40, 2000.0, 0.0).rowNdcY);
}

TEST(OceanGrid, IndicesDrawRowsFrontToBack) {
    const int columns = 7, rows = 5;
    const std::vector<std::uint32_t> indices = oceanGridIndices(columns, rows);
    ASSERT_EQ(indices.size(), std::size_t((columns - 1) * (rows - 1) * 6));
    for (std::uint32_t i : indices) EXPECT_LT(i, std::uint32_t(columns * rows));

    const OceanCamera cam = makeCamera({0, 10.0, 0}, -25.0, 0.0, 60.0, 1.5);
    const OceanGrid grid = projectOceanGrid(cam, 0.0, columns, rows);
    ASSERT_TRUE(grid.visible);
    const auto position = [&](std::uint32_t i) { return oceanGridVertex(grid, int(i) % columns, int(i) / columns); };

    int previousRow = 0;
    std::vector<int> quadUses((columns - 1) * (rows - 1), 0);
    for (std::size_t q = 0; q < indices.size(); q += 6) {
        // Each quad is two triangles sharing a diagonal, covering exactly the quad's corners.
        std::vector<std::uint32_t> corners(indices.begin() + q, indices.begin() + q + 6);
        const std::uint32_t lowest = *std::min_element(corners.begin(), corners.end());
        const int row = int(lowest) / columns, column = int(lowest) % columns;
        ASSERT_LT(column, columns - 1);
        ASSERT_LT(row, rows - 1);
        std::vector<std::uint32_t> expected{lowest, lowest + 1, lowest + columns, lowest + columns + 1};
        std::sort(corners.begin(), corners.end());
        corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
        EXPECT_EQ(corners, expected);
        ++quadUses[row * (columns - 1) + column];
        EXPECT_GE(row, previousRow);  // every triangle of row r before any of row r + 1
        previousRow = row;
        for (std::size_t tri = q; tri < q + 6; tri += 3) {
            const int triRow = int(std::min({indices[tri], indices[tri + 1], indices[tri + 2]})) / columns;
            EXPECT_EQ(triRow, row);
            // Counter-clockwise seen from above: the face normal points up.
            const glm::dvec3 a = position(indices[tri]), b = position(indices[tri + 1]), c = position(indices[tri + 2]);
            EXPECT_GT(glm::cross(b - a, c - a).y, 0.0);
        }
    }
    for (int uses : quadUses) EXPECT_EQ(uses, 1);
}

TEST(OceanGrid, NdcBufferMatchesTheGrid) {
    const OceanCamera cam = makeCamera({0, 10.0, 0}, -25.0, 0.0, 60.0, 1.5);
    const OceanGrid grid = projectOceanGrid(cam, 0.0, 5, 6);
    const std::vector<float> ndc = oceanGridNdcBuffer(grid);
    ASSERT_EQ(ndc.size(), std::size_t(5 * 6 * 2));
    for (int r = 0; r < 6; ++r)
        for (int c = 0; c < 5; ++c) {
            EXPECT_FLOAT_EQ(ndc[(r * 5 + c) * 2], float(-1.0 + 2.0 * c / 4.0));
            EXPECT_FLOAT_EQ(ndc[(r * 5 + c) * 2 + 1], float(grid.rowNdcY[r]));
        }
}

TEST(OceanWaves, PackForGpuFollowsTheDocumentedLayout) {
    const WaveSet set = defaultWaves();
    const OceanWavesGpu g = packForGpu(set);
    EXPECT_FLOAT_EQ(g.dirs01[2], float(set.waves[1].direction.x));
    EXPECT_FLOAT_EQ(g.dirs01[3], float(set.waves[1].direction.y));
    EXPECT_FLOAT_EQ(g.dirs23[0], float(set.waves[2].direction.x));
    EXPECT_FLOAT_EQ(g.steepness[3], float(set.waves[3].steepness));
    EXPECT_FLOAT_EQ(g.noiseDriftY[2], float(set.noiseDrift[2].y));
    EXPECT_FLOAT_EQ(g.noiseAmplitude, float(set.noiseAmplitude));
}
