// The runtime's baked lighting (ARCHITECTURE.md section 7): a tower on open ground, baked by
// bake::bakeCity, drawn with and without its bake on llvmpipe.
#include "golden.hpp"
#include "render_support.hpp"
#include "test_support.hpp"

#include <dawnforge/bake/bake.hpp>
#include <dawnforge/core/materials.hpp>
#include <dawnforge/core/scene.hpp>
#include <dawnforge/exporters/gltf.hpp>
#include <dawnforge/exporters/image.hpp>
#include <dawnforge/runtime/context.hpp>
#include <dawnforge/runtime/lightmaps.hpp>
#include <dawnforge/runtime/renderer.hpp>

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

using namespace dawnforge;
using namespace dawnforge::runtime;
using dawnforge::test::TempDir;

namespace {

constexpr glm::ivec2 kSize{160, 120};
// In the 160 × 120 picture: open ground far from the tower (bottom left), and the ground in
// the tower's shadow at its foot (right of it), picked on the picture.
constexpr int kOpen[4] = {0, 104, 24, 120};
constexpr int kFoot[4] = {84, 60, 96, 66};

GlContext& context() { return test::llvmpipeContext(); }

// A parallelogram from `corner` along a and b facing `normal` (wound to agree), uv0 in metres.
void addQuad(Mesh& m, glm::vec3 corner, glm::vec3 a, glm::vec3 b, glm::vec3 normal, std::uint8_t material) {
    if (glm::dot(glm::cross(a, b), normal) < 0.0f) std::swap(a, b);
    const auto base = std::uint32_t(m.positions.size());
    const glm::vec3 corners[4] = {corner, corner + a, corner + a + b, corner + b};
    const glm::vec2 uv[4] = {{0, 0}, {glm::length(a), 0}, {glm::length(a), glm::length(b)}, {0, glm::length(b)}};
    for (int k = 0; k < 4; ++k) {
        m.positions.push_back(corners[k]);
        m.normals.push_back(normal);
        m.uv0.push_back(uv[k]);
        m.uv1.emplace_back(0.0f);
        m.uv2.emplace_back(0.0f);
        m.materialIds.push_back(material);
    }
    m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
}

// 60 × 60 m of ground and a closed 6 × 6 × 14 m tower at the origin; baked coarsely.
std::filesystem::path bakedTower(const TempDir& dir) {
    Mesh ground, tower;
    ground.name = "ground_0_0";
    tower.name = "building_00000_lod0";
    addQuad(ground, {-30, 0, -30}, {60, 0, 0}, {0, 0, 60}, {0, 1, 0}, kGround);
    const glm::vec3 lo(-3, 0, -3), x(6, 0, 0), y(0, 14, 0), z(0, 0, 6);
    addQuad(tower, lo, y, z, {-1, 0, 0}, kPlaster);
    addQuad(tower, lo + x, y, z, {1, 0, 0}, kPlaster);
    addQuad(tower, lo, x, y, {0, 0, -1}, kPlaster);
    addQuad(tower, lo + z, x, y, {0, 0, 1}, kPlaster);
    addQuad(tower, lo + y, x, z, {0, 1, 0}, kRoofFlat);
    const std::filesystem::path city = dir / "city";
    std::filesystem::create_directories(city);
    Scene scene;
    scene.addMeshNode(std::move(ground));
    scene.addMeshNode(std::move(tower));
    exporters::writeGlb(scene, city / "city.glb");
    test::writeText(city / "city.json", R"({"counts": {"buildings": 1}})");
    bake::BakeSettings settings;
    settings.texel = 0.5;
    settings.groundTexel = 0.5;
    settings.samples = 64;
    settings.sunSamples = 8;
    bake::bakeCity(city, settings);
    return city;
}

exporters::Image render(const std::filesystem::path& city, double hours) {
    context();
    SceneFile scene;
    scene.cityDir = city;
    scene.exposure.fixed = 1.0;  // the test compares light with and without the bake: auto exposure would even it out
    RendererOptions options;
    options.size = kSize;
    options.shadowMapSize = 1024;
    Renderer renderer(scene, options);
    FrameSettings frame;
    frame.camera.position = {16, 12, 22};
    frame.camera.forward = glm::normalize(glm::dvec3(0, 1, 0) - frame.camera.position);
    frame.camera.fovYDegrees = 60.0;
    frame.timeOfDay = hours;
    renderer.render(frame);
    return renderer.readPixels();
}

double luminance(const exporters::Image& image, int x0, int y0, int x1, int y1) {
    double sum = 0.0;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
            const std::size_t p = (std::size_t(y) * std::size_t(image.width) + std::size_t(x)) * 4;
            sum += 0.2126 * image.rgba[p] + 0.7152 * image.rgba[p + 1] + 0.0722 * image.rgba[p + 2];
        }
    return sum / double((x1 - x0) * (y1 - y0));
}

}  // namespace

TEST(BakedRender, OpenGroundLooksTheSameAndTheTowersFootIsDarker) {
    TempDir dir;
    const std::filesystem::path city = bakedTower(dir);
    const exporters::Image baked = render(city, 13.0);
    // The golden image's tolerances are the other render tests' (golden.hpp): llvmpipe and the
    // bake are both deterministic, so any change is a change of the shading or of the bake.
    test::expectGolden("baked_tower", baked);
    if (std::getenv("DAWNFORGE_KEEP_PICTURES")) exporters::writePng(baked, "/tmp/dawnforge_baked_tower.png");
    std::filesystem::rename(city / "bake", dir / "bake.off");
    const exporters::Image plain = render(city, 13.0);
    if (std::getenv("DAWNFORGE_KEEP_PICTURES")) exporters::writePng(plain, "/tmp/dawnforge_plain_tower.png");
    // Open ground: baked R = 1 and AO = 1 give the same light as the unbaked sky term; 2 %
    // allows for the 8-bit sqrt encoding and the little sun bounce the bake adds (measured
    // +0.1 %).
    const auto lum = [](const exporters::Image& image, const int (&r)[4]) { return luminance(image, r[0], r[1], r[2], r[3]); };
    const double open = lum(baked, kOpen) / lum(plain, kOpen);
    EXPECT_NEAR(open, 1.0, 0.02);
    // In the tower's shadow at its foot only sky light is left, and the tower hides part of
    // that sky: the bake darkens it, the unbaked hemisphere term does not (measured 0.906;
    // 0.95 leaves room for driver rounding, not for a missing bake).
    EXPECT_LT(lum(baked, kFoot) / lum(plain, kFoot), 0.95 * open);
}
