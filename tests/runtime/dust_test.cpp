// The destructions' dust (runtime/src/scene_dust.cpp, shaders/dust.*) on llvmpipe: a VAT's
// puffs show where they float in open air, are hidden behind a wall, fade softly where they
// meet it, and show nothing at opacity 0. Pictures compared with the same scene without dust
// at a pinned exposure (the automatic one would follow the dust's light).
#include "render_support.hpp"
#include "test_support.hpp"

#include <dawnforge/core/primitives.hpp>
#include <dawnforge/exporters/gltf.hpp>
#include <dawnforge/exporters/vat.hpp>
#include <dawnforge/runtime/renderer.hpp>
#include <dawnforge/runtime/scene_file.hpp>

#include <gtest/gtest.h>

using namespace dawnforge;
using namespace dawnforge::exporters;
using namespace dawnforge::runtime;
using dawnforge::test::TempDir;

namespace {

constexpr glm::ivec2 kSize{160, 120};

// A brick wall facing +z at z = -2, x in [-8, 8], y in [0, 8].
void writeWall(const std::filesystem::path& dir) {
    Mesh wall = makeBox({-8, 0, -2.4}, {8, 8, -2}, 2);  // brick: the grey dust shows against it
    std::filesystem::create_directories(dir);
    Scene scene;
    scene.addMeshNode(std::move(wall));
    writeGlb(scene, dir / "city.glb");
}

struct PuffSpec {
    glm::vec3 centre;
    float size, opacity;
};

// A VAT of one box far behind the camera and `puffs`, still over 2 frames.
void writeVatWithDust(const std::filesystem::path& dir, const std::vector<PuffSpec>& puffs) {
    const std::vector<Mesh> pieces{makeBox({-0.5, -0.5, -0.5}, {0.5, 0.5, 0.5}, 3)};
    std::vector<float> transforms, dust;
    for (int k = 0; k < 2; ++k) {
        transforms.insert(transforms.end(), {0.0f, 1.0f, 60.0f, 0.0f, 0.0f, 0.0f, 1.0f});
        for (const PuffSpec& p : puffs) dust.insert(dust.end(), {p.centre.x, p.centre.y, p.centre.z, p.size, p.opacity});
    }
    VatAnimation animation{pieces, transforms, 2, 30.0, {}, dust, puffs.size()};
    VatSettings settings;
    settings.name = "dusty";
    writeVat(encodeVat(animation, settings), settings, dir);
}

// The wall of CITY and a VAT of `puffs` written to DIR, at 0.01 s.
Image render(const std::filesystem::path& city, const std::filesystem::path& dir, const std::vector<PuffSpec>& puffs) {
    writeVatWithDust(dir / "vat", puffs);
    SceneFile scene;
    scene.cityDir = city;
    scene.exposure.fixed = 0.3;
    scene.destruction.push_back({dir / "vat", "dusty", glm::dvec3(0.0), 0.0, 0.0, std::nullopt});
    test::llvmpipeContext();
    RendererOptions options;
    options.size = kSize;
    Renderer renderer(scene, options);
    FrameSettings frame = test::lookingAt({0, 4, 12}, {0, 4, 0});
    frame.time = 0.01;
    renderer.render(frame);
    return renderer.readPixels();
}

// The largest colour difference in a square of half-width 3 around (x, y).
double difference(const Image& a, const Image& b, int cx, int cy) {
    double most = 0.0;
    for (int y = cy - 3; y <= cy + 3; ++y)
        for (int x = cx - 3; x <= cx + 3; ++x)
            for (int c = 0; c < 3; ++c) {
                const std::size_t i = (std::size_t(y) * std::size_t(a.width) + std::size_t(x)) * 4 + std::size_t(c);
                most = std::max(most, std::abs(double(a.rgba[i]) - double(b.rgba[i])));
            }
    return most;
}

}  // namespace

// Three puffs 2 m across, opacity 0.55, seen against the wall 14 m away: one 1.5 m in front of
// it (left), one 0.5 m behind it (right: hidden, though it faces the camera 14° off the wall's
// normal), one 10 cm in front (middle: faded by the soft edge to a fifth, as it nearly touches
// the wall). Pixel columns: the camera's 50° vertical view at
// 4:3 is ±31.9° across, 10.3 px a metre at the first puff's 12.5 m, 9.2 at the wall's 14 m.
TEST(Dust, PuffsShowInTheAirHideBehindWallsAndFadeWhereTheyMeetThem) {
    TempDir dir;
    writeWall(dir / "city");
    const Image none = render(dir / "city", dir / "none", {{glm::vec3(0, 4, 60), 1.0f, 0.0f}});
    const Image dusty = render(dir / "city", dir / "dusty", {{glm::vec3(-3.5f, 4, -0.5f), 2.0f, 0.55f},
                                                {glm::vec3(3.5f, 4, -2.5f), 2.0f, 0.55f},
                                                {glm::vec3(0, 4, -1.9f), 2.0f, 0.55f}});
    const int row = 60;
    const double open = difference(none, dusty, 44, row);     // the puff in the air, at x = -3.5
    const double hidden = difference(none, dusty, 112, row);  // behind the wall, at x = 3.5
    const double touching = difference(none, dusty, 80, row);            // 10 cm in front of it
    std::printf("dust: open %g, hidden %g, touching %g\n", open, hidden, touching);
    EXPECT_GT(open, 30.0) << "a puff in open air shows";
    EXPECT_EQ(hidden, 0.0) << "a puff behind the wall is hidden";
    EXPECT_GT(touching, 0.0) << "a puff near the wall still shows a little";
    EXPECT_LT(touching, 0.5 * open) << "a puff near the wall is faded by the soft edge";
    // Far from every puff, nothing changes.
    EXPECT_EQ(difference(none, dusty, 10, 10), 0.0);
    // At opacity 0 the puffs draw nothing at all.
    const Image clear = render(dir / "city", dir / "clear", {{glm::vec3(-3.5f, 4, -0.5f), 2.0f, 0.0f}});
    EXPECT_EQ(clear.rgba, none.rgba);
}
