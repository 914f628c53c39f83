// animatePieces: a simulation as a glTF animation. The GLB is read back here with its own
// reader (JSON + BIN chunk, accessors by hand) and sampled at every frame as a glTF reader
// samples LINEAR channels; every pose must come back within the tolerances.
#include "test_support.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/primitives.hpp>
#include <dawnforge/exporters/animation.hpp>
#include <dawnforge/exporters/gltf.hpp>

#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>

using namespace dawnforge;
using namespace dawnforge::exporters;
using dawnforge::test::TempDir;

namespace {

constexpr int kFrames = 90;
constexpr double kFps = 30.0;

// Four pieces: one that sleeps, one sliding and spinning steadily, one falling and wobbling
// (a parabola: at 0.5 mm every frame is a key), one turning slowly whose quaternion the file
// gives with the sign flipped every other frame.
struct Motion {
    std::vector<Mesh> pieces{makeBox({-0.5f, -0.5f, -0.5f}, {0.5f, 0.5f, 0.5f}), makeIcosphere(0.4f, 1),
                             makeBox({-0.1f, -0.2f, -0.3f}, {0.1f, 0.2f, 0.3f}), makeIcosphere(0.2f, 1)};
    std::vector<std::string> names{"resting", "sliding", "falling", "flipped"};
    std::vector<float> transforms;
    Motion() {
        for (int k = 0; k < kFrames; ++k) {
            const double t = k / kFps;
            const glm::dquat spin = glm::angleAxis(7.0 * t, glm::normalize(glm::dvec3(1, 2, 3)));
            const glm::dquat wobble = glm::angleAxis(0.3 * std::sin(4.0 * t), glm::dvec3(0, 1, 0));
            const glm::dquat slow = glm::angleAxis(1.0 * t, glm::dvec3(0, 0, 1));
            put({1, 0.5, 2}, glm::dquat(1, 0, 0, 0));
            put({4 * t, 0.4, -2 * t}, spin);
            put({-3, 1 + 12 * t - 4.905 * t * t, 0}, wobble);
            put({2, 0.2, 5}, k % 2 ? -slow : slow);
        }
    }
    void put(glm::dvec3 p, glm::dquat q) {
        transforms.insert(transforms.end(), {float(p.x), float(p.y), float(p.z), float(q.x), float(q.y), float(q.z),
                                             float(q.w)});
    }
    PieceMotion view() const { return {pieces, names, transforms, kFrames, kFps}; }
};

// The GLB's JSON and the floats of an accessor, read without tinygltf.
struct Glb {
    nlohmann::json json;
    std::vector<std::byte> bytes;
    std::size_t bin = 0;
    explicit Glb(std::vector<std::byte> glb) : bytes(std::move(glb)) {
        std::uint32_t length = 0;
        std::memcpy(&length, bytes.data() + 12, 4);
        json = nlohmann::json::parse(std::string(reinterpret_cast<const char*>(bytes.data()) + 20, length));
        bin = 20 + length + 8;
    }
    std::vector<float> floats(int accessor) const {
        const nlohmann::json& a = json["accessors"][accessor];
        const nlohmann::json& v = json["bufferViews"][a["bufferView"].get<int>()];
        EXPECT_EQ(a["componentType"], 5126);
        const std::size_t width = a["type"] == "SCALAR" ? 1 : a["type"] == "VEC3" ? 3 : 4;
        std::vector<float> out(a["count"].get<std::size_t>() * width);
        std::memcpy(out.data(), bytes.data() + bin + v.value("byteOffset", 0) + a.value("byteOffset", 0),
                    out.size() * 4);
        return out;
    }
};

// A LINEAR channel sampled at time t: the values around it blended (slerp for quaternions).
std::vector<double> sample(const std::vector<float>& times, const std::vector<float>& values, std::size_t width,
                           double t) {
    std::size_t i = 0;
    while (i + 2 < times.size() && times[i + 1] <= t) ++i;
    const double s = times.size() == 1 ? 0.0 : std::clamp((t - times[i]) / (times[i + 1] - times[i]), 0.0, 1.0);
    const std::size_t j = std::min(i + 1, times.size() - 1);
    std::vector<double> out(width);
    if (width == 4) {
        const glm::dquat a(values[4 * i + 3], values[4 * i], values[4 * i + 1], values[4 * i + 2]);
        const glm::dquat b(values[4 * j + 3], values[4 * j], values[4 * j + 1], values[4 * j + 2]);
        const glm::dquat q = glm::slerp(a, b, s);
        out = {q.x, q.y, q.z, q.w};
    } else {
        for (std::size_t c = 0; c < width; ++c) out[c] = values[width * i + c] * (1 - s) + values[width * j + c] * s;
    }
    return out;
}

struct Worst {
    double position = 0.0, degrees = 0.0;
};

// Every frame of every piece, as the GLB plays it, against the motion.
Worst replay(const Glb& glb, const Motion& motion) {
    Worst worst;
    const nlohmann::json& animation = glb.json["animations"][0];
    for (const nlohmann::json& channel : animation["channels"]) {
        const int node = channel["target"]["node"];
        const nlohmann::json& sampler = animation["samplers"][channel["sampler"].get<int>()];
        EXPECT_EQ(sampler.value("interpolation", "LINEAR"), "LINEAR");
        const std::vector<float> times = glb.floats(sampler["input"]), values = glb.floats(sampler["output"]);
        const bool rotation = channel["target"]["path"] == "rotation";
        const std::size_t piece = std::size_t(std::find(motion.names.begin(), motion.names.end(),
                                                        glb.json["nodes"][node]["name"].get<std::string>()) -
                                              motion.names.begin());
        for (int k = 0; k < kFrames; ++k) {
            const std::vector<double> got = sample(times, values, rotation ? 4 : 3, k / kFps);
            const float* want = motion.transforms.data() + (std::size_t(k) * motion.pieces.size() + piece) * 7;
            if (rotation) {
                const double dot = got[0] * want[3] + got[1] * want[4] + got[2] * want[5] + got[3] * want[6];
                worst.degrees = std::max(worst.degrees, 2.0 * std::acos(std::min(1.0, std::abs(dot))) * 180.0 / M_PI);
            } else {
                worst.position = std::max(worst.position, std::hypot(got[0] - want[0], got[1] - want[1], got[2] - want[2]));
            }
        }
    }
    return worst;
}

}  // namespace

TEST(Animation, EveryFramePlaysBackWithinTheTolerances) {
    const Motion motion;
    const PieceAnimation anim = animatePieces(motion.view());
    const Glb glb(encodeGlb(anim.scene));
    ASSERT_EQ(glb.json["animations"].size(), 1u);
    EXPECT_EQ(glb.json["animations"][0]["name"], "simulation");
    EXPECT_EQ(glb.json["animations"][0]["channels"].size(), 8u);  // a translation and a rotation per piece
    const Worst worst = replay(glb, motion);
    EXPECT_LT(worst.position, 0.001);
    EXPECT_LT(worst.degrees, 0.1);
    EXPECT_LE(anim.maxPositionError, AnimationSettings{}.positionTolerance);
    EXPECT_LE(anim.maxRotationError, AnimationSettings{}.rotationTolerance);
}

TEST(Animation, NodesAreNamedAndStandAtTheFirstFrame) {
    const Motion motion;
    const Glb glb(encodeGlb(animatePieces(motion.view()).scene));
    ASSERT_EQ(glb.json["nodes"].size(), 4u);
    for (std::size_t i = 0; i < 4; ++i) {
        const nlohmann::json& node = glb.json["nodes"][i];
        EXPECT_EQ(node["name"], motion.names[i]);
        const nlohmann::json t = node.value("translation", nlohmann::json::array({0.0, 0.0, 0.0}));
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(t[c].get<double>(), motion.transforms[7 * i + std::size_t(c)], 1e-6);
    }
}

TEST(Animation, KeysAreDroppedWhereTheMotionIsLinear) {
    const Motion motion;
    const PieceAnimation anim = animatePieces(motion.view());
    const NodeTrack& resting = anim.scene.animations[0].tracks[0];
    EXPECT_EQ(resting.translations.size(), 2u);  // the first and the last frame
    EXPECT_EQ(resting.rotations.size(), 2u);
    // Sliding at a steady speed: two keys; spinning at 7 rad/s (13.4° a frame): slerp is exact,
    // so keys only where 30° would be passed: every second frame.
    const NodeTrack& sliding = anim.scene.animations[0].tracks[1];
    EXPECT_EQ(sliding.translations.size(), 2u);
    const int gap = int((M_PI / 6.0) / (7.0 / kFps));
    EXPECT_EQ(sliding.rotations.size(), std::size_t((kFrames - 1 + gap - 1) / gap + 1));
    // Falling: g (Δt)² / 8 is 1.4 mm between frames, so every frame is a key.
    EXPECT_EQ(anim.scene.animations[0].tracks[2].translations.size(), std::size_t(kFrames));
    // Signs flipped every other frame are the same rotation: a slow turn needs few keys, all in
    // one hemisphere.
    const NodeTrack& flipped = anim.scene.animations[0].tracks[3];
    EXPECT_LE(flipped.rotations.size(), std::size_t(1.0 * (kFrames - 1) / kFps / (M_PI / 6.0)) + 3);
    for (std::size_t k = 1; k < flipped.rotations.size(); ++k)
        EXPECT_GE(glm::dot(flipped.rotations[k - 1], flipped.rotations[k]), 0.0f);
    // A looser tolerance keeps fewer keys and still holds.
    AnimationSettings loose;
    loose.positionTolerance = 0.05;
    const PieceAnimation coarse = animatePieces(motion.view(), loose);
    EXPECT_LT(coarse.translationKeys, anim.translationKeys / 2);
    EXPECT_LE(coarse.maxPositionError, 0.05);
    EXPECT_GT(coarse.maxPositionError, 0.01);
}

TEST(Animation, SameMotionSameBytesAndAValidFile) {
    const Motion motion;
    const std::vector<std::byte> a = encodeGlb(animatePieces(motion.view()).scene);
    EXPECT_EQ(a, encodeGlb(animatePieces(motion.view()).scene));
    TempDir dir;
    writeGlb(animatePieces(motion.view()).scene, dir / "anim.glb");
    test::expectValidGltf(dir / "anim.glb");
}

TEST(Animation, AMotionThatDoesNotFitItsPiecesIsRefused) {
    Motion motion;
    PieceMotion view = motion.view();
    view.frames = kFrames + 1;
    EXPECT_THROW(animatePieces(view), InputError);
    view = motion.view();
    view.fps = 0.0;
    EXPECT_THROW(animatePieces(view), InputError);
    motion.names.pop_back();
    EXPECT_THROW(animatePieces(motion.view()), InputError);
}
