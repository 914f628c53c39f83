#pragma once
// Bullet for the two passes that use it (sim/src only; no Bullet type leaves the module):
// glm <-> Bullet conversions and a piece's collision hull.
#include <dawnforge/sim/rigidbody.hpp>

#include <BulletCollision/CollisionShapes/btBvhTriangleMeshShape.h>
#include <BulletCollision/CollisionShapes/btTriangleIndexVertexArray.h>
#include <LinearMath/btQuaternion.h>
#include <LinearMath/btVector3.h>
#include <glm/gtc/constants.hpp>
#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

namespace dawnforge::sim {

inline btVector3 bt(const glm::dvec3& v) { return btVector3(btScalar(v.x), btScalar(v.y), btScalar(v.z)); }
inline glm::dvec3 toGlm(const btVector3& v) { return {double(v.x()), double(v.y()), double(v.z())}; }
inline btQuaternion bt(const glm::dquat& q) { return btQuaternion(btScalar(q.x), btScalar(q.y), btScalar(q.z), btScalar(q.w)); }
inline glm::dquat toGlm(const btQuaternion& q) { return glm::dquat(double(q.w()), double(q.x()), double(q.y()), double(q.z())); }

// The collision hull of one piece in the frame `axes` (its principal frame, or the identity
// for its mesh frame): the convex hull of the mesh, shrunk by the margin (Bullet adds it
// back), cut down to a vertex budget by farthest point sampling (ties to the lowest index, so
// the choice is deterministic).
struct Hull {
    std::vector<btVector3> points;
    btScalar margin = 0;
};

Hull buildHull(const RigidPiece& piece, const glm::dmat3& axes, int budget, double margin);

// A static collider mesh as Bullet reads it: the triangle arrays it points into, kept with it.
// `mesh` must have triangles (Bullet's BVH builder crashes on an empty mesh).
struct ColliderShape {
    std::vector<int> indices;
    std::vector<btScalar> vertices;
    std::unique_ptr<btTriangleIndexVertexArray> array;
    std::unique_ptr<btBvhTriangleMeshShape> shape;
};
std::unique_ptr<ColliderShape> colliderShape(const Mesh& mesh);

// Whether a body at `p` is over the support's footprint: there the support holds it and the
// colliders let it through; elsewhere the colliders hold it.
inline bool overSupport(const Support& s, const btVector3& p) {
    return p.x() >= s.min.x && p.x() <= s.max.x && p.z() >= s.min.y && p.z() <= s.max.y;
}

// Turns along a path of orientations (a body's, substep by substep): `q` after `path`, always
// far below half a turn apart, taken the near way; returns the angle (rad) and moves `path` on.
inline double followTurn(glm::dquat& path, glm::dquat q) {
    const double d = glm::dot(q, path);
    if (d < 0.0) q = -q;
    path = q;
    return 2.0 * std::acos(std::min(1.0, std::abs(d)));
}

// turns.bin's value for `travelled` radians along a path that ended at `path`, where the frame
// was recorded as `recorded`: negative when the path ends at its negation.
inline float signedTurns(double travelled, const glm::dquat& path, const glm::dquat& recorded) {
    const double turns = travelled / glm::two_pi<double>();
    return float(glm::dot(path, recorded) < 0.0 ? -turns : turns);
}

}  // namespace dawnforge::sim
