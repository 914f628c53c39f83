// The Labs VAT 3.0 Non-HDR form (`vat --format ldr`), checked from the outside: the three PNGs,
// the mesh and _data.json are read back and every vertex decoded in float32 as the Labs shaders
// do (Unity: the URP_VAT3 rigid-body graph, its material properties; Unreal: the material's
// codes read from the mesh bounds), then compared with the animation computed in double.
#include "test_support.hpp"

#include <dawnforge/core/import.hpp>
#include <dawnforge/core/primitives.hpp>
#include <dawnforge/exporters/image.hpp>
#include <dawnforge/exporters/vat.hpp>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <set>
#include <string>
#include <vector>

namespace dawnforge::exporters {

namespace {

constexpr int kFrames = 10;
constexpr int kWidth = 2;  // 5 pieces: 3 rows per frame

float frac(float x) { return x - std::floor(x); }

// Five pieces thrown 40 m apart while they spin about different axes, so that each of the
// four packing cases (the quaternion component dropped) occurs; piece 4 rests.
struct Animation {
    std::vector<Mesh> pieces;
    std::vector<float> transforms;

    explicit Animation(bool spin = true) {
        const glm::dvec3 axes[] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}, {0, 1, 0}};
        const double degrees[] = {35.0, 41.0, 47.0, 29.0, 0.0};
        for (int j = 0; j < 5; ++j) pieces.push_back(makeBox({-0.3f, -0.2f, -0.5f}, {0.3f + 0.1f * float(j), 0.2f, 0.5f}));
        for (int k = 0; k < kFrames; ++k)
            for (int j = 0; j < 5; ++j) {
                const glm::dvec3 p = glm::dvec3(3.0 * j - 5.0, 1.0, -2.0) + double(k) * glm::dvec3(4.0 - j, 0.5, 1.5 * j - 3.0);
                const glm::dquat q = glm::angleAxis(glm::radians(spin ? degrees[j] * k : 0.0), glm::normalize(axes[j]));
                for (double v : {p.x, p.y, p.z, q.x, q.y, q.z, q.w}) transforms.push_back(float(v));
            }
    }
    VatAnimation view() const { return {pieces, transforms, kFrames, 30.0}; }
    glm::dvec3 position(int k, int j) const {
        const float* t = transforms.data() + (std::size_t(k) * 5 + std::size_t(j)) * 7;
        return {t[0], t[1], t[2]};
    }
    glm::dquat orientation(int k, int j) const {
        const float* t = transforms.data() + (std::size_t(k) * 5 + std::size_t(j)) * 7;
        return glm::normalize(glm::dquat(t[6], t[3], t[4], t[5]));
    }
};

// Our axes → the engine's: Unity mirrors x; Unreal is (x, z, y) in centimetres.
glm::dvec3 toEngine(VatPreset preset, const glm::dvec3& p) {
    return preset == VatPreset::Unity ? glm::dvec3(-p.x, p.y, p.z) : 100.0 * glm::dvec3(p.x, p.z, p.y);
}

// The Labs case tables (Unity graph's Decode_Quaternion; the Unreal material's), (x, y, z, w).
glm::vec4 decodeQuaternion(VatPreset preset, const glm::vec3& c, int m) {
    const float w = std::sqrt(std::max(0.0f, 1.0f - glm::dot(c, c)));
    if (m == 0 || m > 3) return {c.x, c.y, c.z, w};
    if (preset == VatPreset::Unity) {
        if (m == 1) return {w, c.y, c.z, c.x};
        if (m == 2) return {c.x, -w, c.z, -c.y};
        return {c.x, c.y, -w, -c.z};
    }
    if (m == 1) return {-w, c.y, c.z, -c.x};
    if (m == 2) return {c.x, c.y, -w, -c.z};
    return {c.x, -w, c.z, -c.y};
}

glm::vec3 rotate(const glm::vec4& q, const glm::vec3& v) {
    const glm::vec3 u(q);
    return v + 2.0f * glm::cross(u, glm::cross(u, v) + q.w * v);
}

glm::vec4 texel(const Image& image, int row, int column) {
    const std::size_t at = (std::size_t(row) * std::size_t(image.width) + std::size_t(column)) * 4;
    return glm::vec4(image.rgba[at], image.rgba[at + 1], image.rgba[at + 2], image.rgba[at + 3]) / 255.0f;
}

// What a Labs material is told: the bounds it lerps positions between and reads its codes
// from (Unity: the material properties; Unreal: the mesh's bounds, data triangles included).
struct Material {
    glm::vec3 lo{0.0f}, hi{0.0f};
    float maxTurns = 0.0f, maxScale = 0.0f;
    bool hdr = true, twoTextures = false;
};

Material readMaterial(VatPreset preset, const nlohmann::json& data, const Mesh& mesh) {
    Material m;
    if (preset == VatPreset::Unity) {
        const nlohmann::json& u = data.at("unity_material");
        m.lo = {u.at("_boundMinX").get<float>(), u.at("_boundMinY").get<float>(), u.at("_boundMinZ").get<float>()};
        m.hi = {u.at("_boundMaxX").get<float>(), u.at("_boundMaxY").get<float>(), u.at("_boundMaxZ").get<float>()};
        m.hdr = frac(10.0f * m.hi.z) >= 0.5f;
        m.maxTurns = 1.0f / (1.0f - frac(-10.0f * m.lo.x));
        m.maxScale = 1.0f / (1.0f - frac(10.0f * m.hi.y));
        m.twoTextures = u.at("_B_LOAD_POS_TWO_TEX").get<int>() == 1;
        return m;
    }
    m.lo = glm::vec3(std::numeric_limits<float>::max());
    m.hi = -m.lo;
    for (const glm::vec3& p : mesh.positions) {
        const glm::vec3 e = 100.0f * glm::vec3(p.x, p.z, p.y);
        m.lo = glm::min(m.lo, e), m.hi = glm::max(m.hi, e);
    }
    const glm::vec3 dm = glm::round(m.hi / 1e-4f) * 1e-4f * 0.1f;  // decimetres, as the material reads them
    const float code = frac(dm.y);
    m.hdr = code >= 0.5f;
    m.twoTextures = frac(code / 0.5f) >= 0.5f;  // [0.25, 0.5) or [0.75, 1)
    m.maxTurns = 1.0f / (1.0f - frac(dm.x));
    m.maxScale = 1.0f / (1.0f - frac(dm.z));
    return m;
}

struct Baked {
    test::TempDir dir;
    nlohmann::json data;
    Mesh mesh;
    Image pos, pos2, rot;

    Baked(const Animation& animation, VatPreset preset, bool single = false) {
        VatSettings settings;
        settings.preset = preset;
        settings.format = VatFormat::Ldr;
        settings.singlePositionTexture = single;
        settings.maxWidth = kWidth;
        settings.name = "crate";
        writeVat(encodeVat(animation.view(), settings), settings, dir.path());
        data = nlohmann::json::parse(test::readText(dir / "crate_data.json"));
        mesh = loadMeshNodes(dir / "crate_mesh.glb").at(0).mesh;
        pos = readPng(dir / "crate_pos.png");
        if (!single) pos2 = readPng(dir / "crate_pos2.png");
        rot = readPng(dir / "crate_rot.png");
    }
};

TEST(VatLdr, TheLabsDecodersReadEveryVertexWithinTheStatedError) {
    const Animation animation;
    for (const VatPreset preset : {VatPreset::Unity, VatPreset::Unreal}) {
        SCOPED_TRACE(std::string(vatPresetName(preset)));
        const Baked b(animation, preset);
        EXPECT_FALSE(std::filesystem::exists(b.dir / "crate_pos.exr"));
        EXPECT_EQ(b.data.at("texture_format"), "ldr");
        EXPECT_EQ(b.data.at("textures").at("position2"), "crate_pos2.png");
        for (const Image* image : {&b.pos, &b.pos2, &b.rot}) {
            EXPECT_EQ(image->width, kWidth);
            EXPECT_EQ(image->height, 3 * kFrames);
        }
        const Material material = readMaterial(preset, b.data, b.mesh);
        EXPECT_FALSE(material.hdr);
        EXPECT_TRUE(material.twoTextures);
        EXPECT_NEAR(material.maxTurns, 1.0f, 1e-4f) << "no piece turns a whole turn per frame";
        const double s = preset == VatPreset::Unreal ? 100.0 : 1.0;
        const double stated = b.data.at("max_vertex_error").get<double>();
        // What 8 bits allow: positions to 1/51000 of the bounds, orientations to 2√3/255 rad
        // (0.78°) and a little more where the rebuilt component takes the others' rounding
        // (measured 0.0147 rad), scales to 1.5/255.
        EXPECT_LT(b.data.at("max_position_error").get<double>(), 60.0 / 51000.0);
        EXPECT_LT(b.data.at("max_rotation_error").get<double>(), 0.016);
        EXPECT_NEAR(b.data.at("max_scale_error").get<double>(), 1.5 / 253.5, 1e-6);

        std::vector<std::size_t> seen(5, 0);
        double worst = 0.0;
        std::set<int> cases;
        for (std::size_t i = 0; i < b.mesh.positions.size(); ++i) {
            const std::uint32_t j = b.mesh.pieceIds[i];
            if (j == 5) continue;  // a data triangle
            const std::size_t local = seen[j]++;
            const glm::dvec3 rest(animation.pieces[j].positions[local]);
            const glm::vec3 restEngine(toEngine(preset, animation.position(0, int(j)) + rest));
            const glm::vec3 pivotEngine(toEngine(preset, animation.position(0, int(j))));
            for (int k = 0; k < kFrames; ++k) {
                const int row = k * 3 + int(j) / kWidth, column = int(j) % kWidth;
                const glm::vec4 p = texel(b.pos, row, column), p2 = texel(b.pos2, row, column);
                const glm::vec4 r = (texel(b.rot, row, column) - 0.5f) * 2.0f;
                const glm::vec3 position = (glm::vec3(p) + glm::vec3(p2) * 0.01f) * (material.hi - material.lo) + material.lo;
                const int m = int(std::floor(4.0f * p.w));
                cases.insert(m);
                const float scale = (1.0f - frac(4.0f * p.w)) * material.maxScale;
                const glm::vec3 got = rotate(decodeQuaternion(preset, glm::vec3(r), m), restEngine - pivotEngine) * scale + position;
                const glm::dvec3 want =
                    toEngine(preset, animation.orientation(k, int(j)) * rest + animation.position(k, int(j)));
                const double error = glm::length(glm::dvec3(got) - want) / s;
                worst = std::isnan(error) ? error : std::max(worst, error);
                if (k + 1 < kFrames) {
                    EXPECT_NE(r.w, 0.0f) << "0.5 has no byte: a turn of 0 is stored just above";
                }
            }
        }
        EXPECT_EQ(cases, (std::set<int>{0, 1, 2, 3})) << "the animation no longer exercises every packing case";
        EXPECT_LE(worst, stated * 1.001 + 1e-6);
        EXPECT_GT(worst, 0.1 * stated) << "the stated error is far above what the decoder reads";
        EXPECT_LT(worst, 0.02) << "a 1.2 m piece within 2 cm";
    }
}

// The signed turns keep their sign in 8 bits: a turn stored on the wrong side of 0.5 would
// slerp the other way round.
TEST(VatLdr, TurnsKeepTheirSign) {
    const Animation animation;
    VatSettings hdr, ldr;
    hdr.preset = ldr.preset = VatPreset::Unity;
    ldr.format = VatFormat::Ldr;
    const Vat a = encodeVat(animation.view(), hdr), b = encodeVat(animation.view(), ldr);
    ASSERT_EQ(a.rotation.size(), b.rotation.size());
    int negative = 0;
    for (std::size_t i = 3; i < a.rotation.size(); i += 4) {
        const float decoded = (b.rotation[i] - 0.5f) * 2.0f;
        EXPECT_EQ(decoded < 0.0f, a.rotation[i] < 0.0f) << i;
        EXPECT_NEAR(decoded, a.rotation[i], 1.0f / 255.0f + 1e-6f) << i;
        negative += a.rotation[i] < 0.0f;
    }
    EXPECT_GT(negative, 0) << "no frame pair with a hemisphere flip";
}

// Without rotations only case 0 occurs, and its alpha decodes a scale of exactly 1. The
// identity itself has no 8-bit form: (0 + 1) / 2 falls between two bytes, so each component is
// 1/255 off and a piece at rest is turned by 2√3/255 rad (0.78°), the form's worst case.
TEST(VatLdr, AnAnimationWithoutTurnsKeepsEveryScaleExact) {
    const Animation still(false);
    VatSettings settings;
    settings.preset = VatPreset::Unreal;
    settings.format = VatFormat::Ldr;
    const Vat vat = encodeVat(still.view(), settings);
    EXPECT_EQ(vat.maxScaleError, 0.0);
    EXPECT_NEAR(vat.maxRotationError, 2.0 * std::sqrt(3.0) / 255.0, 1e-5);
    for (std::size_t i = 0; i < vat.rotation.size(); ++i)
        EXPECT_TRUE(vat.rotation[i] == 127.0f / 255.0f || vat.rotation[i] == 128.0f / 255.0f) << i;
}

TEST(VatLdr, RefusesHalfAndTheNativePreset) {
    const Animation animation;
    VatSettings settings;
    settings.format = VatFormat::Ldr;
    settings.preset = VatPreset::Native;
    EXPECT_TRUE(test::contains(test::inputErrorOf([&] { encodeVat(animation.view(), settings); }), "unity and unreal presets"));
    settings.preset = VatPreset::Unity;
    settings.half = true;
    EXPECT_TRUE(test::contains(test::inputErrorOf([&] { encodeVat(animation.view(), settings); }), "--half is for the hdr"));
    EXPECT_EQ(parseVatFormat("ldr"), VatFormat::Ldr);
    EXPECT_EQ(parseVatFormat("hdr"), VatFormat::Hdr);
    EXPECT_FALSE(parseVatFormat("png").has_value());
}

// --single-position-texture: no _pos2, the switch off in the codes and the Unity keyword, and
// each position rounded to the nearest 1/255 of the bounds.
TEST(VatLdr, OneTextureHoldsPositionsToA510thOfTheBounds) {
    const Animation animation;
    for (const VatPreset preset : {VatPreset::Unity, VatPreset::Unreal}) {
        SCOPED_TRACE(std::string(vatPresetName(preset)));
        const Baked b(animation, preset, true);
        EXPECT_FALSE(std::filesystem::exists(b.dir / "crate_pos2.png"));
        EXPECT_FALSE(b.data.at("textures").contains("position2"));
        const Material material = readMaterial(preset, b.data, b.mesh);
        EXPECT_FALSE(material.hdr);
        EXPECT_FALSE(material.twoTextures);
        const double s = preset == VatPreset::Unreal ? 100.0 : 1.0;
        const glm::dvec3 extent = glm::dvec3(material.hi - material.lo) / s;
        const double position = b.data.at("max_position_error").get<double>();
        EXPECT_LE(position, 0.5 / 255.0 * glm::length(extent) + 1e-6);
        EXPECT_GT(position, 0.1 / 255.0 * std::min({extent.x, extent.y, extent.z})) << "not rounded to 8 bits";
        double worst = 0.0;
        for (int k = 0; k < kFrames; ++k)
            for (int j = 0; j < 5; ++j) {
                const glm::vec4 p = texel(b.pos, k * 3 + j / kWidth, j % kWidth);
                const glm::dvec3 got = glm::dvec3(glm::vec3(p) * (material.hi - material.lo) + material.lo);
                worst = std::max(worst, glm::length(got - toEngine(preset, animation.position(k, j))) / s);
            }
        EXPECT_LE(worst, position * 1.001 + 1e-6);
    }
    VatSettings hdr;
    hdr.singlePositionTexture = true;
    EXPECT_TRUE(test::contains(test::inputErrorOf([&] { encodeVat(animation.view(), hdr); }), "for the ldr format"));
}

TEST(VatLdr, SameAnimationSameBytes) {
    const Animation animation;
    const Baked a(animation, VatPreset::Unreal), b(animation, VatPreset::Unreal);
    for (const char* file : {"crate_pos.png", "crate_pos2.png", "crate_rot.png", "crate_mesh.glb", "crate_data.json"})
        EXPECT_EQ(test::readText(a.dir / file), test::readText(b.dir / file)) << file;
}

}  // namespace

}  // namespace dawnforge::exporters
