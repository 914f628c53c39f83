#pragma once
// A simulation as a glTF animation: one node per piece, its motion as keys that a linear
// interpolation (slerp for rotations) brings back within a tolerance of every frame, so that
// any glTF reader (Blender, three.js, Godot, an engine without the Labs shaders) can play it.
#include <dawnforge/core/scene.hpp>

#include <cstddef>
#include <numbers>
#include <span>
#include <string>

namespace dawnforge::exporters {

struct PieceMotion {
    std::span<const Mesh> pieces;              // relative to each piece's pivot, world axes
    std::span<const std::string> names;        // per piece: the nodes' names
    std::span<const float> transforms;         // frames × pieces × (position x, y, z, quaternion x, y, z, w)
    int frames = 0;
    double fps = 0.0;
};

struct AnimationSettings {
    std::string name = "simulation";
    double positionTolerance = 0.0005;                      // m, at every frame
    double rotationTolerance = 0.05 * std::numbers::pi / 180.0;  // rad, at every frame
    // The most a piece turns between two keys (rad): readers that blend quaternions linearly
    // (Blender) stay within 0.04° of slerp up to 30°.
    double maxKeyTurn = 30.0 * std::numbers::pi / 180.0;
};

struct PieceAnimation {
    Scene scene;                  // a node per piece (at its first frame's pose) and one animation
    std::size_t translationKeys = 0, rotationKeys = 0;
    double maxPositionError = 0.0;  // m: the keys interpolated against every frame
    double maxRotationError = 0.0;  // rad
};

// Throws InputError when the motion does not fit its pieces (sizes, frames, fps).
PieceAnimation animatePieces(const PieceMotion& motion, const AnimationSettings& settings = {});

}  // namespace dawnforge::exporters
