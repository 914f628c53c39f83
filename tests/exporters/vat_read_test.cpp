// readVat: what writeVat wrote comes back unchanged, and a damaged or mismatched VAT folder
// fails with an InputError that names the file at fault.
#include "test_support.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/isolate.hpp>
#include <dawnforge/core/seed.hpp>
#include <dawnforge/core/primitives.hpp>
#include <dawnforge/exporters/vat.hpp>
#include <dawnforge/exporters/vat_read.hpp>

#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace dawnforge::exporters {

namespace {

using test::inputErrorOf;
using test::contains;

constexpr int kFrames = 5;
constexpr double kFps = 24.0;

// `count` boxes falling and turning: enough to fill several rows per frame at width 3.
struct Animation {
    std::vector<Mesh> pieces;
    std::vector<float> transforms;

    explicit Animation(int count) {
        for (int j = 0; j < count; ++j) {
            const float h = 0.1f + 0.02f * float(j);
            pieces.push_back(makeBox({-h, -0.1f, -0.15f}, {h, 0.1f, 0.15f}));
        }
        for (int k = 0; k < kFrames; ++k)
            for (int j = 0; j < count; ++j) {
                const glm::dvec3 p(0.4 * j, 1.0 + 0.1 * j - 0.2 * k, -0.3 * j + 0.05 * k);
                const glm::dquat q = glm::angleAxis(glm::radians(17.0 * k * (j + 1)), glm::normalize(glm::dvec3(1, j, 2)));
                for (double v : {p.x, p.y, p.z, q.x, q.y, q.z, q.w}) transforms.push_back(float(v));
            }
    }
    VatAnimation view() const { return {pieces, transforms, kFrames, kFps}; }
};

// Bakes `pieces` boxes as DIR/<name>_* and returns what the encoder produced.
Vat bake(const std::filesystem::path& dir, const std::string& name, int pieces, bool half = false,
         VatPreset preset = VatPreset::Native) {
    const Animation animation(pieces);
    VatSettings settings;
    settings.name = name;
    settings.half = half;
    settings.maxWidth = 3;
    settings.preset = preset;
    Vat vat = encodeVat(animation.view(), settings);
    writeVat(vat, settings, dir);
    return vat;
}

void expectSameVat(const Vat& vat, const VatFile& read, bool half) {
    EXPECT_EQ(read.layout.pieces, vat.layout.pieces);
    EXPECT_EQ(read.layout.frames, vat.layout.frames);
    EXPECT_EQ(read.layout.width, vat.layout.width);
    EXPECT_EQ(read.layout.rowsPerFrame, vat.layout.rowsPerFrame);
    EXPECT_EQ(read.layout.height, vat.layout.height);
    EXPECT_EQ(read.fps, kFps);
    EXPECT_EQ(read.half, half);
    EXPECT_EQ(read.position, vat.position);  // exact: half values were rounded by the encoder already
    EXPECT_EQ(read.rotation, vat.rotation);
    EXPECT_EQ(read.boundsMin, vat.boundsMin);
    EXPECT_EQ(read.boundsMax, vat.boundsMax);
}

}  // namespace

TEST(VatRead, ReadsBackWhatWasWritten) {
    const test::TempDir dir;
    const Vat vat = bake(dir.path(), "crate", 7);
    const VatFile read = readVat(dir.path(), "crate");
    EXPECT_EQ(read.name, "crate");
    EXPECT_EQ(read.preset, VatPreset::Native);
    EXPECT_EQ(read.layout.rowsPerFrame, 3);
    expectSameVat(vat, read, false);
    EXPECT_EQ(read.mesh.triangleCount(), vat.mesh.triangleCount());
    EXPECT_EQ(read.mesh.uv1, vat.mesh.uv1);
    EXPECT_EQ(read.mesh.pieceIds, vat.mesh.pieceIds);
}

TEST(VatRead, ReadsHalfPrecision) {
    const test::TempDir dir;
    const Vat vat = bake(dir.path(), "crate", 7, true);
    const VatFile read = readVat(dir.path(), "crate");
    expectSameVat(vat, read, true);
    EXPECT_EQ(read.mesh.triangleCount(), vat.mesh.triangleCount());
}

TEST(VatRead, DropsTheEngineDataTriangles) {
    const test::TempDir dir;
    const Vat vat = bake(dir.path(), "crate", 7, false, VatPreset::Unity);
    const VatFile read = readVat(dir.path(), "crate");
    EXPECT_EQ(read.preset, VatPreset::Unity);
    EXPECT_EQ(read.mesh.triangleCount(), vat.mesh.triangleCount() - 2);
    for (std::uint32_t id : read.mesh.pieceIds) EXPECT_LT(id, 7u);
}

TEST(VatRead, ListsTheVatsInAFolder) {
    const test::TempDir dir;
    bake(dir.path(), "tower", 4);
    bake(dir.path(), "crate", 3);
    test::writeText(dir / "notes.json", "{}");
    EXPECT_EQ(listVats(dir.path()), (std::vector<std::string>{"crate", "tower"}));
    EXPECT_TRUE(contains(inputErrorOf([&] { listVats(dir / "absent"); }), "absent"));
}

TEST(VatRead, MissingFileIsNamed) {
    const test::TempDir dir;
    bake(dir.path(), "crate", 7);
    std::filesystem::remove(dir / "crate_rot.exr");
    const std::string message = inputErrorOf([&] { readVat(dir.path(), "crate"); });
    EXPECT_TRUE(contains(message, "crate_rot.exr")) << message;
    EXPECT_TRUE(contains(message, "missing")) << message;
}

TEST(VatRead, PiecesThatDisagreeWithTheLayout) {
    const test::TempDir dir;
    bake(dir.path(), "crate", 7);
    const std::string original = test::readText(dir / "crate_data.json");
    nlohmann::ordered_json data = nlohmann::ordered_json::parse(original);
    data["pieces"] = 8;  // 8 pieces at W = 3 still need R = 3: the mesh is what disagrees
    test::writeText(dir / "crate_data.json", data.dump(1));
    std::string message = inputErrorOf([&] { readVat(dir.path(), "crate"); });
    EXPECT_TRUE(contains(message, "crate_mesh.glb")) << message;
    EXPECT_TRUE(contains(message, "pieces")) << message;

    data["pieces"] = 10;  // 10 pieces need 4 rows per frame, but R says 3
    test::writeText(dir / "crate_data.json", data.dump(1));
    message = inputErrorOf([&] { readVat(dir.path(), "crate"); });
    EXPECT_TRUE(contains(message, "crate_data.json")) << message;
    EXPECT_TRUE(contains(message, "\"R\"")) << message;

    data = nlohmann::ordered_json::parse(original);
    data["format"] = "dawnforge.scene";
    test::writeText(dir / "crate_data.json", data.dump(1));
    message = inputErrorOf([&] { readVat(dir.path(), "crate"); });
    EXPECT_TRUE(contains(message, "crate_data.json")) << message;
    EXPECT_TRUE(contains(message, "dawnforge.vat")) << message;

    data = nlohmann::ordered_json::parse(original);
    data["bounds"]["min"][1] = "low";
    test::writeText(dir / "crate_data.json", data.dump(1));
    message = inputErrorOf([&] { readVat(dir.path(), "crate"); });
    EXPECT_TRUE(contains(message, "bounds.min")) << message;

    test::writeText(dir / "crate_data.json", "{\"format\": ");
    message = inputErrorOf([&] { readVat(dir.path(), "crate"); });
    EXPECT_TRUE(contains(message, "crate_data.json")) << message;
    EXPECT_TRUE(contains(message, "not valid JSON")) << message;
}

TEST(VatRead, TextureOfTheWrongSize) {
    const test::TempDir dir, other;
    bake(dir.path(), "crate", 7);
    bake(other.path(), "crate", 4);  // W = 3, R = 2: 3 × 10 instead of 3 × 15
    std::filesystem::copy_file(other / "crate_pos.exr", dir / "crate_pos.exr",
                               std::filesystem::copy_options::overwrite_existing);
    const std::string message = inputErrorOf([&] { readVat(dir.path(), "crate"); });
    EXPECT_TRUE(contains(message, "crate_pos.exr")) << message;
    EXPECT_TRUE(contains(message, "3 × 10")) << message;
}

TEST(VatRead, TextureThatIsNotAnExr) {
    const test::TempDir dir;
    bake(dir.path(), "crate", 7);
    test::writeText(dir / "crate_rot.exr", "not an image");
    const std::string message = inputErrorOf([&] { readVat(dir.path(), "crate"); });
    EXPECT_TRUE(contains(message, "crate_rot.exr")) << message;
}

// OpenEXR is a large parser of binary data, and a user hands in VAT folders: damaged position
// textures (float and half, bytes flipped, cut, spliced, numbers made huge) are read in a
// child process (core/isolate.hpp) and come back as texels that are all finite, or as one
// line naming the file. How often OpenEXR itself crashed or hung is printed.
TEST(VatRead, DamagedTexturesAreReadSafelyOrRefused) {
    const test::TempDir dir;
    const test::ScopedReaderLimits limits({.seconds = DAWNFORGE_SANITIZED ? 5.0 : 2.0, .gigabytes = 2.0});
    Rng rng(deriveSeed(5, "vat-exr-fuzz"));
    std::map<std::string, int> outcomes;
    const int cases = DAWNFORGE_SANITIZED ? 200 : 2000;
    for (int i = 0; i < cases; ++i) {
        const bool half = i % 2 == 1;
        const std::string name = half ? "half" : "full";
        if (i < 2) bake(dir.path(), name, 7, half);
        const std::filesystem::path texture = dir / (name + "_pos.exr"), good = dir / (name + "_pos.good");
        if (i < 2) std::filesystem::copy_file(texture, good);
        std::string bytes = test::readText(good);
        for (int d = rng.range(1, 3); d > 0; --d) test::damage(bytes, bytes, rng);
        std::filesystem::remove(texture);
        test::writeText(texture, bytes);
        try {
            const VatFile read = readVat(dir.path(), name);
            ASSERT_EQ(read.position.size(), std::size_t(read.layout.width) * read.layout.height * 4);
            for (float v : read.position) ASSERT_TRUE(std::isfinite(v)) << "case " << i;
            ++outcomes["read"];
        } catch (const ReaderFailure& e) {
            ++outcomes[std::string("reader ") + (e.kind() == ReaderFailure::Kind::Crashed ? "crashed" : "stopped")];
            ASSERT_TRUE(contains(e.what(), texture.string())) << e.what();
        } catch (const InputError& e) {
            ++outcomes["refused"];
            ASSERT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
        }
    }
    std::string summary;
    for (const auto& [outcome, count] : outcomes) summary += " " + outcome + " " + std::to_string(count) + ";";
    std::printf("%d damaged VAT position textures:%s\n", cases, summary.c_str());
    EXPECT_GT(outcomes["refused"], cases / 4);
}

TEST(VatRead, MeshWithADifferentPieceCount) {
    const test::TempDir dir, other;
    bake(dir.path(), "crate", 7);
    bake(other.path(), "crate", 5);
    std::filesystem::copy_file(other / "crate_mesh.glb", dir / "crate_mesh.glb",
                               std::filesystem::copy_options::overwrite_existing);
    const std::string message = inputErrorOf([&] { readVat(dir.path(), "crate"); });
    EXPECT_TRUE(contains(message, "crate_mesh.glb")) << message;
    EXPECT_TRUE(contains(message, "5 pieces")) << message;
}

TEST(VatRead, MeshWhoseLookupUvsAreNotTexelCentres) {
    // Same piece count, but a layout of 7 pieces in one row (W = 7): every V is off.
    const test::TempDir dir, other;
    bake(dir.path(), "crate", 7);
    {
        const Animation animation(7);
        VatSettings settings;
        settings.name = "crate";
        settings.maxWidth = 7;
        writeVat(encodeVat(animation.view(), settings), settings, other.path());
    }
    std::filesystem::copy_file(other / "crate_mesh.glb", dir / "crate_mesh.glb",
                               std::filesystem::copy_options::overwrite_existing);
    const std::string message = inputErrorOf([&] { readVat(dir.path(), "crate"); });
    EXPECT_TRUE(contains(message, "crate_mesh.glb")) << message;
    EXPECT_TRUE(contains(message, "lookup UV")) << message;
}

}  // namespace dawnforge::exporters
