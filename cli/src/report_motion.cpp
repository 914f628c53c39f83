// The simulation's energy and pieces in motion per frame, for report.html: sim.json stores only
// the energy's initial, largest and final values, so the frames come from transforms.bin and
// the fracture's masses (ARCHITECTURE.md, section 4.3).
#include "report_parts.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/read_file.hpp>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>

#include <cstring>

namespace dawnforge::cli::report {

namespace {

constexpr double kGravity = 9.81;  // m/s², as SimulationSettings' default

struct PieceState {
    glm::dvec3 position{0.0};
    glm::dquat orientation{1.0, 0.0, 0.0, 0.0};
};

PieceState stateAt(std::span<const float> transforms, std::size_t pieces, int frame, std::size_t piece) {
    const float* t = transforms.data() + (std::size_t(frame) * pieces + piece) * 7;
    return {{t[0], t[1], t[2]}, glm::normalize(glm::dquat(t[6], t[3], t[4], t[5]))};
}

// Angular velocity (rad/s, world axes) that turns `a` into `b` in `dt` along the shorter way.
glm::dvec3 spinBetween(const glm::dquat& a, const glm::dquat& b, double dt) {
    glm::dquat d = b * glm::conjugate(a);
    if (d.w < 0.0) d = -d;
    const glm::dvec3 axis(d.x, d.y, d.z);
    const double s = glm::length(axis);
    if (s < 1e-12) return glm::dvec3(0.0);
    return axis / s * (2.0 * std::atan2(s, d.w) / dt);
}

}  // namespace

Motion motionOf(std::span<const float> transforms, std::span<const PieceMass> pieces, int frames, double fps) {
    const std::size_t n = pieces.size();
    DAWNFORGE_ASSERT(frames >= 1 && fps > 0.0 && transforms.size() == std::size_t(frames) * n * 7, "frames × pieces × 7 floats");
    Motion m;
    for (int k = 0; k < frames; ++k) {
        const int a = std::max(k - 1, 0), b = std::min(k + 1, frames - 1);
        const double dt = (b - a) / fps;
        double kinetic = 0.0, potential = 0.0, moving = 0.0;
        for (std::size_t i = 0; i < n; ++i) {
            const PieceState now = stateAt(transforms, n, k, i), before = stateAt(transforms, n, a, i),
                             after = stateAt(transforms, n, b, i);
            const glm::dvec3 v = dt > 0.0 ? (after.position - before.position) / dt : glm::dvec3(0.0);
            const glm::dvec3 w = dt > 0.0 ? spinBetween(before.orientation, after.orientation, dt) : glm::dvec3(0.0);
            const std::array<double, 9>& I = pieces[i].inertia;
            const glm::dmat3 rest(I[0], I[3], I[6], I[1], I[4], I[7], I[2], I[5], I[8]);  // glm is column-major
            const glm::dmat3 r = glm::mat3_cast(now.orientation);
            kinetic += 0.5 * pieces[i].mass * glm::dot(v, v) + 0.5 * glm::dot(w, r * rest * glm::transpose(r) * w);
            potential += pieces[i].mass * kGravity * now.position.y;
            moving += (glm::length(v) > kMovingSpeed || glm::length(w) > kMovingSpin) ? 1.0 : 0.0;
        }
        m.time.push_back(k / fps);
        m.kinetic.push_back(kinetic);
        m.potential.push_back(potential);
        m.moving.push_back(moving);
    }
    return m;
}

namespace {

std::vector<PieceMass> piecesOf(const std::filesystem::path& fractureDir) {
    const auto file = fractureDir / "fracture.json";
    const nlohmann::json j = nlohmann::json::parse(readTextFile(file), nullptr, false);
    if (j.is_discarded() || !j.contains("pieces") || !j["pieces"].is_array())
        throw InputError(format("{}: no pieces array", file.string()));
    std::vector<PieceMass> pieces;
    for (const nlohmann::json& p : j["pieces"]) {
        PieceMass piece;
        piece.mass = p.at("mass").get<double>();
        for (std::size_t r = 0; r < 3; ++r)
            for (std::size_t c = 0; c < 3; ++c) piece.inertia[r * 3 + c] = p.at("inertia").at(r).at(c).get<double>();
        pieces.push_back(piece);
    }
    return pieces;
}

}  // namespace

Motion readMotion(const std::filesystem::path& simDir, const std::filesystem::path& fractureDir) {
    const nlohmann::json sim = nlohmann::json::parse(readTextFile(simDir / "sim.json"), nullptr, false);
    if (sim.is_discarded() || !sim.is_object()) throw InputError(format("{}: not JSON", (simDir / "sim.json").string()));
    const int frames = sim.value("frames", 0);
    const double fps = sim.value("fps", 0.0);
    const std::vector<PieceMass> pieces = piecesOf(fractureDir);
    const std::size_t chips = sim.value("debris", nlohmann::json::object()).value("chips", std::size_t(0));
    const std::size_t all = pieces.size() + chips;  // the chips of debris follow the pieces
    if (frames < 1 || !(fps > 0.0) || sim.value("pieces", std::size_t(0)) != all)
        throw InputError(format("{}: frames, fps or pieces do not match {}", (simDir / "sim.json").string(),
                                (fractureDir / "fracture.json").string()));
    const std::vector<std::byte> bytes = readBinaryFile(simDir / "transforms.bin");
    if (bytes.size() != std::size_t(frames) * all * 7 * sizeof(float))
        throw InputError(format("{}: {} bytes, expected {}", (simDir / "transforms.bin").string(), bytes.size(),
                                std::size_t(frames) * all * 7 * sizeof(float)));
    std::vector<float> transforms(std::size_t(frames) * pieces.size() * 7);
    for (std::size_t f = 0; f < std::size_t(frames); ++f)  // little-endian, as this machine
        std::memcpy(transforms.data() + f * pieces.size() * 7, bytes.data() + f * all * 7 * sizeof(float),
                    pieces.size() * 7 * sizeof(float));
    for (float v : transforms)
        if (!std::isfinite(v)) throw InputError(format("{}: a value is not finite", (simDir / "transforms.bin").string()));
    return motionOf(transforms, pieces, frames, fps);
}

}  // namespace dawnforge::cli::report
