// One room lit by the sky through a window, against an independent brute-force path tracer:
// its own ray–rectangle intersection and its own random numbers (std::mt19937_64), nothing
// shared with the baker but the room's description.
#include "scene_builder.hpp"

#include <dawnforge/bake/lighting.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <random>
#include <vector>

namespace dawnforge::bake {
namespace {

struct Rect {
    glm::dvec3 corner, a, b, normal;  // normal: the side light comes from (into the room)
};

// The room: [0, 4] × [0, 3] × [0, 4], normals inwards, a 2 × 1.5 m window in the z = 0 wall.
std::vector<Rect> roomRects() {
    std::vector<Rect> r;
    const auto add = [&](glm::dvec3 c, glm::dvec3 a, glm::dvec3 b, glm::dvec3 n) { r.push_back({c, a, b, n}); };
    add({0, 0, 0}, {0, 3, 0}, {0, 0, 4}, {1, 0, 0});
    add({4, 0, 0}, {0, 3, 0}, {0, 0, 4}, {-1, 0, 0});
    add({0, 0, 0}, {4, 0, 0}, {0, 0, 4}, {0, 1, 0});
    add({0, 3, 0}, {4, 0, 0}, {0, 0, 4}, {0, -1, 0});
    add({0, 0, 4}, {4, 0, 0}, {0, 3, 0}, {0, 0, -1});
    add({0, 0, 0}, {4, 0, 0}, {0, 1, 0}, {0, 0, 1});      // below the window
    add({0, 2.5, 0}, {4, 0, 0}, {0, 0.5, 0}, {0, 0, 1});  // above it
    add({0, 1, 0}, {1, 0, 0}, {0, 1.5, 0}, {0, 0, 1});    // left of it
    add({3, 1, 0}, {1, 0, 0}, {0, 1.5, 0}, {0, 0, 1});    // right of it
    return r;
}

// The nearest rectangle a ray meets (front or back), and where.
std::optional<std::pair<std::size_t, glm::dvec3>> nearest(const std::vector<Rect>& rects, glm::dvec3 o, glm::dvec3 d) {
    double best = INFINITY;
    std::optional<std::pair<std::size_t, glm::dvec3>> hit;
    for (std::size_t i = 0; i < rects.size(); ++i) {
        const Rect& r = rects[i];
        const double denom = glm::dot(d, r.normal);
        if (std::abs(denom) < 1e-12) continue;
        const double t = glm::dot(r.corner - o, r.normal) / denom;
        if (t <= 1e-6 || t >= best) continue;
        const glm::dvec3 p = o + t * d - r.corner;
        const double u = glm::dot(p, r.a) / glm::dot(r.a, r.a), v = glm::dot(p, r.b) / glm::dot(r.b, r.b);
        if (u < 0.0 || u > 1.0 || v < 0.0 || v > 1.0) continue;
        best = t;
        hit = std::make_pair(i, o + t * d);
    }
    return hit;
}

// Irradiance with `bounces` bounces left: the same model as the bake (sky of radiance 1/π
// above the horizon, nothing below it, Lambertian walls of albedo a), one path per call.
double pathIrradiance(const std::vector<Rect>& rects, glm::dvec3 x, glm::dvec3 n, int bounces, double albedo, std::mt19937_64& rng) {
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    const double u1 = uniform(rng), u2 = uniform(rng);
    const double r = std::sqrt(u1), phi = 2.0 * 3.14159265358979323846 * u2;
    const glm::dvec3 t = std::abs(n.x) > 0.5 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0);
    const glm::dvec3 e1 = glm::normalize(glm::cross(t, n)), e2 = glm::cross(n, e1);
    const glm::dvec3 d = r * std::cos(phi) * e1 + r * std::sin(phi) * e2 + std::sqrt(1.0 - u1) * n;
    const auto hit = nearest(rects, x, d);
    if (!hit) return d.y > 0.0 ? 1.0 : 0.0;
    const Rect& wall = rects[hit->first];
    if (bounces == 0 || glm::dot(wall.normal, d) > 0.0) return 0.0;
    return albedo * pathIrradiance(rects, hit->second, wall.normal, bounces - 1, albedo, rng);
}

TEST(Reference, ARoomLitThroughItsWindowAgreesWithABruteForcePathTracer) {
    const double albedo = 0.6;
    const int bounces = 2;
    test::ReceiverBuilder room;
    for (const Rect& r : roomRects())
        room.quad(glm::vec3(r.corner), glm::vec3(r.a), glm::vec3(r.b), glm::vec3(r.normal), 0.25f);
    LightingSettings settings;
    settings.samples = 256;
    settings.bounces = bounces;
    settings.albedo.fill(float(albedo));
    const ReceiverInput input = room.input();
    const Lighting lit = bakeLighting(std::span(&input, 1), {}, {}, settings);
    const std::vector<TexelSample> samples = sampleTexels(room.chartMesh(), room.layout);
    // Floor texels in the middle of the room (away from the edges' texel samples).
    const std::vector<Rect> rects = roomRects();
    std::mt19937_64 rng(12345);
    double baked = 0.0, traced = 0.0;
    int points = 0;
    for (const TexelSample& s : samples) {
        if (s.normal.y < 0.99f || s.position.x < 1.0f || s.position.x > 3.0f || s.position.z < 0.5f || s.position.z > 3.5f)
            continue;
        if (points % 4 == 0) {  // every fourth texel: 32 of them, 4096 paths each
            baked += lit.receivers[0].channels[4 * std::size_t(s.texel)];
            double sum = 0.0;
            for (int k = 0; k < 4096; ++k) sum += pathIrradiance(rects, glm::dvec3(s.position) + glm::dvec3(0, 1e-4, 0), {0, 1, 0}, bounces, albedo, rng);
            traced += sum / 4096.0;
        }
        ++points;
    }
    const int used = (points + 3) / 4;
    ASSERT_GE(used, 24);
    baked /= used, traced /= used;
    // Measured: 0.0730 baked against 0.0710 traced (+2.8 %). The tracer's mean has a standard
    // error of about 1 % (131,072 paths); the baker's bounces are gathered at every other
    // texel and read bilinearly. 5 % covers both, not a lost bounce or a leak.
    EXPECT_GT(traced, 0.05);
    EXPECT_NEAR(baked, traced, 0.05 * traced);
}

}  // namespace
}  // namespace dawnforge::bake
