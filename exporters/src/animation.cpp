// A simulation as a glTF animation: keys kept greedily, each segment checked against every frame
// it spans. glTF 2.0 spec, "Animations": LINEAR translations interpolate linearly, rotations by
// slerp.
#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/exporters/animation.hpp>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace dawnforge::exporters {

namespace {

// The angle of the turn from a to b (rad), well conditioned near zero, whichever sign b has.
double turnBetween(const glm::dquat& a, glm::dquat b) {
    if (glm::dot(a, b) < 0.0) b = -b;
    // a and b, as unit 4-vectors, lie half the turn's angle apart.
    return 4.0 * std::atan2(glm::length(glm::dvec4(a.x - b.x, a.y - b.y, a.z - b.z, a.w - b.w)),
                            glm::length(glm::dvec4(a.x + b.x, a.y + b.y, a.z + b.z, a.w + b.w)));
}

// The keys of one channel: from each kept frame, the furthest next frame whose segment
// `error(a, c, j)` keeps every frame j between within `tolerance` (and `fits(a, c)`); the first
// and last frames are always keys.
template <typename Error, typename Fits>
std::vector<int> keepKeys(int frames, double tolerance, Error&& error, Fits&& fits) {
    auto segmentFits = [&](int a, int c) {
        if (!fits(a, c)) return false;
        for (int j = a + 1; j < c; ++j)
            if (error(a, c, j) > tolerance) return false;
        return true;
    };
    std::vector<int> kept{0};
    for (int a = 0; a < frames - 1;) {
        int c = a + 1;
        while (c + 1 < frames && segmentFits(a, c + 1)) ++c;
        kept.push_back(c);
        a = c;
    }
    return kept;
}

// The worst error of the kept keys over every frame.
template <typename Error>
double worstError(const std::vector<int>& kept, Error&& error) {
    double worst = 0.0;
    for (std::size_t k = 0; k + 1 < kept.size(); ++k)
        for (int j = kept[k] + 1; j < kept[k + 1]; ++j) worst = std::max(worst, error(kept[k], kept[k + 1], j));
    return worst;
}

void checkMotion(const PieceMotion& motion) {
    if (motion.frames < 1 || !(motion.fps > 0.0) || !std::isfinite(motion.fps))
        throw InputError(format("an animation needs at least one frame and a positive frame rate (got {} frames at {} "
                                "fps)",
                                motion.frames, motion.fps));
    if (motion.names.size() != motion.pieces.size())
        throw InputError(format("{} piece names for {} pieces", motion.names.size(), motion.pieces.size()));
    const std::size_t expected = std::size_t(motion.frames) * motion.pieces.size() * 7;
    if (motion.transforms.size() != expected)
        throw InputError(format("{} transform values for {} frames of {} pieces (expected {})",
                                motion.transforms.size(), motion.frames, motion.pieces.size(), expected));
}

struct PieceTrack {
    NodeTrack track;
    double positionError = 0.0, rotationError = 0.0;
};

PieceTrack trackPiece(const PieceMotion& motion, std::size_t piece, const AnimationSettings& settings) {
    const int frames = motion.frames;
    std::vector<glm::dvec3> position(std::size_t(frames), glm::dvec3(0.0));
    std::vector<glm::dquat> rotation(std::size_t(frames), glm::dquat(1.0, 0.0, 0.0, 0.0));
    for (int k = 0; k < frames; ++k) {
        const float* t = motion.transforms.data() + (std::size_t(k) * motion.pieces.size() + piece) * 7;
        position[std::size_t(k)] = glm::dvec3(t[0], t[1], t[2]);
        glm::dquat q = glm::normalize(glm::dquat(t[6], t[3], t[4], t[5]));
        // One hemisphere from frame to frame: readers that blend components (Blender) then
        // take the short way, as slerp does.
        if (k > 0 && glm::dot(rotation[std::size_t(k - 1)], q) < 0.0) q = -q;
        rotation[std::size_t(k)] = q;
    }
    auto along = [](int a, int c, int j) { return double(j - a) / double(c - a); };
    auto positionError = [&](int a, int c, int j) {
        return glm::length(glm::mix(position[std::size_t(a)], position[std::size_t(c)], along(a, c, j)) -
                           position[std::size_t(j)]);
    };
    auto rotationError = [&](int a, int c, int j) {
        return turnBetween(glm::slerp(rotation[std::size_t(a)], rotation[std::size_t(c)], along(a, c, j)),
                           rotation[std::size_t(j)]);
    };
    const std::vector<int> moves =
        keepKeys(frames, settings.positionTolerance, positionError, [](int, int) { return true; });
    const std::vector<int> turns = keepKeys(frames, settings.rotationTolerance, rotationError, [&](int a, int c) {
        return turnBetween(rotation[std::size_t(a)], rotation[std::size_t(c)]) <= settings.maxKeyTurn;
    });

    PieceTrack out;
    const auto time = [&](int k) { return static_cast<float>(k / motion.fps); };
    for (int k : moves) {
        out.track.translationTimes.push_back(time(k));
        out.track.translations.push_back(glm::vec3(position[std::size_t(k)]));
    }
    for (int k : turns) {
        out.track.rotationTimes.push_back(time(k));
        out.track.rotations.push_back(glm::quat(rotation[std::size_t(k)]));
    }
    out.positionError = worstError(moves, positionError);
    out.rotationError = worstError(turns, rotationError);
    return out;
}

}  // namespace

PieceAnimation animatePieces(const PieceMotion& motion, const AnimationSettings& settings) {
    checkMotion(motion);
    PieceAnimation out;
    Animation animation;
    animation.name = settings.name;
    for (std::size_t i = 0; i < motion.pieces.size(); ++i) {
        Mesh mesh = motion.pieces[i];
        mesh.name = motion.names[i];
        const std::uint32_t node = out.scene.addMeshNode(std::move(mesh));  // named as its mesh
        PieceTrack piece = trackPiece(motion, i, settings);
        out.scene.nodes[node].translation = piece.track.translations.front();
        out.scene.nodes[node].rotation = piece.track.rotations.front();
        out.translationKeys += piece.track.translations.size();
        out.rotationKeys += piece.track.rotations.size();
        out.maxPositionError = std::max(out.maxPositionError, piece.positionError);
        out.maxRotationError = std::max(out.maxRotationError, piece.rotationError);
        piece.track.node = node;
        animation.tracks.push_back(std::move(piece.track));
    }
    out.scene.animations.push_back(std::move(animation));
    return out;
}

}  // namespace dawnforge::exporters
