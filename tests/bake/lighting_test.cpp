// The four channels against analytic answers (issue: baked lighting, "Correct against references").
#include "scene_builder.hpp"

#include <dawnforge/bake/lighting.hpp>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <numeric>

namespace dawnforge::bake {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct TexelValues {
    std::vector<TexelSample> samples;
    std::vector<glm::vec4> values;  // per sample: R, G, B, A
};

TexelValues sampled(const test::ReceiverBuilder& r, const ReceiverLighting& lit) {
    TexelValues out;
    out.samples = sampleTexels(r.chartMesh(), r.layout);
    for (const TexelSample& s : out.samples) {
        const float* v = &lit.channels[4 * std::size_t(s.texel)];
        out.values.emplace_back(v[0], v[1], v[2], v[3]);
    }
    return out;
}

Lighting bakeOne(test::ReceiverBuilder& r, const LightingSettings& settings, std::span<const Lamp> lamps = {}) {
    const ReceiverInput input = r.input();
    return bakeLighting(std::span(&input, 1), lamps, {}, settings);
}

// View factor from a point to an axis-aligned rectangle in a parallel plane at height c, with
// the point's projection at a corner of it (Howell's catalogue, configuration B-3).
double cornerViewFactor(double a, double b, double c) {
    if (a == 0.0 || b == 0.0) return 0.0;
    const double sa = std::copysign(1.0, a), sb = std::copysign(1.0, b);
    const double A = std::abs(a) / c, B = std::abs(b) / c;
    const double f = (A / std::sqrt(1 + A * A) * std::atan(B / std::sqrt(1 + A * A)) +
                      B / std::sqrt(1 + B * B) * std::atan(A / std::sqrt(1 + B * B))) / (2.0 * kPi);
    return sa * sb * f;
}
// ... and to the rectangle [x0, x1] × [z0, z1] anywhere in that plane (signed corner sums).
double rectangleViewFactor(glm::dvec2 p, glm::dvec2 lo, glm::dvec2 hi, double c) {
    return cornerViewFactor(hi.x - p.x, hi.y - p.y, c) - cornerViewFactor(lo.x - p.x, hi.y - p.y, c) -
           cornerViewFactor(hi.x - p.x, lo.y - p.y, c) + cornerViewFactor(lo.x - p.x, lo.y - p.y, c);
}

TEST(Lighting, AnOpenPlaneSeesTheWholeSkyAndNoOcclusion) {
    test::ReceiverBuilder plane;
    plane.quad({-10, 0, -10}, {20, 0, 0}, {0, 0, 20}, {0, 1, 0}, 1.0f);
    LightingSettings settings;
    settings.samples = 32;
    const Lighting lit = bakeOne(plane, settings);
    const TexelValues t = sampled(plane, lit.receivers[0]);
    ASSERT_GT(t.values.size(), 300u);
    for (const glm::vec4& v : t.values) {
        EXPECT_FLOAT_EQ(v.r, 1.0f);  // every cosine ray escapes upwards
        EXPECT_FLOAT_EQ(v.b, 1.0f);  // nothing within the AO radius
        EXPECT_FLOAT_EQ(v.g, 0.0f);  // nothing to bounce the sun from
        EXPECT_FLOAT_EQ(v.a, 0.0f);
    }
}

TEST(Lighting, AFloorSeesTheSkyThroughTheViewFactorOfItsOpening) {
    // A 4 × 4 m room, 3 m high, open at the top; no bounces, so R is the direct sky alone:
    // the fraction of cosine-weighted rays through the opening, i.e. its view factor.
    test::ReceiverBuilder well;
    const bool open[6] = {false, false, false, true, false, false};
    well.room({0, 0, 0}, {4, 3, 4}, 0.25f, open);
    LightingSettings settings;
    settings.samples = 256;
    settings.bounces = 0;
    const Lighting lit = bakeOne(well, settings);
    const TexelValues t = sampled(well, lit.receivers[0]);
    double baked = 0.0, exact = 0.0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < t.samples.size(); ++i) {
        const TexelSample& s = t.samples[i];
        if (s.normal.y < 0.99f) continue;  // the floor's texels
        baked += t.values[i].r;
        exact += rectangleViewFactor({s.position.x, s.position.z}, {0, 0}, {4, 4}, 3.0 - s.position.y);
        ++n;
    }
    ASSERT_GT(n, 200u);
    baked /= double(n), exact /= double(n);
    // 0.36 at the centre, less towards the walls; 256 stratified rays on each of 256 texels:
    // the mean within 0.01 of the exact one.
    EXPECT_GT(exact, 0.15);
    EXPECT_NEAR(baked, exact, 0.01);
}

TEST(Lighting, ASealedRoomGetsNoSkyAndNoSun) {
    test::ReceiverBuilder room;
    room.room({0, 0, 0}, {4, 3, 5}, 0.5f);
    LightingSettings settings;
    settings.samples = 64;
    settings.bounces = 2;
    const Lighting lit = bakeOne(room, settings);
    const TexelValues t = sampled(room, lit.receivers[0]);
    ASSERT_GT(t.values.size(), 100u);
    float ao = 0.0f;
    for (const glm::vec4& v : t.values) {
        EXPECT_EQ(v.r, 0.0f);
        EXPECT_EQ(v.g, 0.0f);
        ao += v.b;
    }
    EXPECT_LT(ao / float(t.values.size()), 0.95f);  // the walls occlude near every edge
}

TEST(Lighting, BouncesInAClosedRoomAddUpToTheGeometricSeries) {
    // In a closed room of albedo a, each bounce carries a times the flux of the one before,
    // and all of it lands inside: the area mean of E_0 + ... + E_k is mean(E_0)·(1 - a^(k+1))/(1 - a),
    // whatever the source. The source: one lamp under the ceiling.
    const float albedo = 0.5f;
    const Lamp lamp{{2.0f, 2.7f, 2.0f}, 0};
    double mean[2] = {0.0, 0.0};
    for (int run = 0; run < 2; ++run) {
        test::ReceiverBuilder room;
        room.room({0, 0, 0}, {4, 3, 4}, 0.25f);
        LightingSettings settings;
        settings.samples = 256;
        settings.bounces = run == 0 ? 0 : 3;
        settings.albedo.fill(albedo);
        const Lighting lit = bakeOne(room, settings, std::span(&lamp, 1));
        const TexelValues t = sampled(room, lit.receivers[0]);
        // Area means: the texels whose centre lies inside a face (each 1/16 m²); the texels
        // along the edges sample the edge itself and would count it twice.
        std::size_t n = 0;
        for (std::size_t i = 0; i < t.samples.size(); ++i) {
            const glm::vec3 p = t.samples[i].position;
            const glm::vec3 hi(4, 3, 4);
            int onBoundary = 0;
            for (int k = 0; k < 3; ++k) onBoundary += p[k] < 0.05f || p[k] > hi[k] - 0.05f;
            if (onBoundary != 1) continue;
            mean[run] += t.values[i].a;
            ++n;
        }
        ASSERT_EQ(n, std::size_t(2 * (16 * 16 + 16 * 12 + 16 * 12)));  // every face, 0.25 m texels
        mean[run] /= double(n);
    }
    const double series = (1.0 - std::pow(albedo, 4)) / (1.0 - albedo);  // 1.875
    ASSERT_GT(mean[0], 0.1);
    // Measured 1.886 (+0.6 %): sampling noise, and bounces gathered at every other texel and
    // read bilinearly. 2 % leaves room for the noise of other seeds, not for a lost bounce (6 %).
    EXPECT_NEAR(mean[1] / mean[0], series, 0.02 * series);
}

TEST(Lighting, LampsFollowTheirFalloffAndStopAtWalls) {
    const double q4 = std::pow(2.74 / kLampRange, 4.0);
    EXPECT_NEAR(lampIrradiance({0, 2.74, 0}, {0, 0, 0}, {0, 1, 0}),
                kLampIntensity * (1 - q4) * (1 - q4) / (2.74 * 2.74 + kLampSoftening * kLampSoftening), 1e-12);
    EXPECT_NEAR(lampIrradiance({0, 2.74, 0}, {0, 0, 0}, {0, 1, 0}), 0.97, 0.005);  // as lighting.hpp says
    EXPECT_EQ(lampIrradiance({0, 2, 0}, {0, 0, 0}, {0, -1, 0}), 0.0);           // facing away
    EXPECT_EQ(lampIrradiance({0, 0, 9}, {0, 0, 0}, {0, 0, 1}), 0.0);            // beyond kLampRange
    EXPECT_EQ(lampIrradiance({0, 0, 0}, {0, 1, 0}, {0, -1, 0}), 0.0);           // above its own height
    // A wall between a lamp and a floor: the floor behind it stays dark. The wall is 20 cm thick
    // (two faces and a top): the two faces of a wall of no thickness coincide, and which one a
    // ray meets first is then up to the rays' rounding.
    test::ReceiverBuilder r;
    r.quad({-4, 0, -4}, {8, 0, 0}, {0, 0, 8}, {0, 1, 0}, 0.5f);
    r.quad({-0.1f, 0, -4}, {0, 3, 0}, {0, 0, 8}, {-1, 0, 0}, 0.5f);
    r.quad({0.1f, 0, -4}, {0, 3, 0}, {0, 0, 8}, {1, 0, 0}, 0.5f);
    r.quad({-0.1f, 3, -4}, {0.2f, 0, 0}, {0, 0, 8}, {0, 1, 0}, 0.5f);
    LightingSettings settings;
    settings.samples = 16;
    settings.bounces = 0;
    const Lamp lamp{{-1.5f, 2.5f, 0.0f}, 0};
    const Lighting lit = bakeOne(r, settings, std::span(&lamp, 1));
    const TexelValues t = sampled(r, lit.receivers[0]);
    double lit0 = 0.0, shaded = 0.0;
    for (std::size_t i = 0; i < t.samples.size(); ++i) {
        const TexelSample& s = t.samples[i];
        if (s.normal.y < 0.99f || std::abs(s.position.z) > 1.0f) continue;
        if (s.position.x < -0.5f) lit0 = std::max(lit0, double(t.values[i].a));
        if (s.position.x > 0.5f) shaded = std::max(shaded, double(t.values[i].a));
    }
    EXPECT_GT(lit0, 0.5);
    EXPECT_EQ(shaded, 0.0);
}

TEST(Lighting, ChannelEncodingRoundTripsWithinOneStep) {
    for (int c = 0; c < 4; ++c)
        for (int s = 0; s < 256; ++s) EXPECT_EQ(encodeChannel(decodeChannel(std::uint8_t(s), c), c), s);
    EXPECT_EQ(encodeChannel(-1.0f, 0), 0);
    EXPECT_EQ(encodeChannel(100.0f, 3), 255);
}

TEST(Lighting, SameResultOnAnyThreadCount) {
    test::ReceiverBuilder a;
    const bool open[6] = {false, false, false, true, false, false};
    a.room({0, 0, 0}, {3, 3, 3}, 0.25f, open);
    LightingSettings settings;
    settings.samples = 16;
    const Lamp lamp{{1.5f, 2.7f, 1.5f}, 0};
    const ReceiverInput input = a.input();
    std::vector<float> first;
    for (int threads : {1, 2, 3}) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
        const Lighting lit = bakeLighting(std::span(&input, 1), std::span(&lamp, 1), {}, settings);
        if (first.empty()) first = lit.receivers[0].channels;
        else EXPECT_EQ(lit.receivers[0].channels, first) << threads << " threads";
    }
}

}  // namespace
}  // namespace dawnforge::bake
