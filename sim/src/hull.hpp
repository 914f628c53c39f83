#pragma once
// Bullet for the two passes that use it (sim/src only; no Bullet type leaves the module):
// glm <-> Bullet conversions and a piece's collision hull.
#include <dawnforge/sim/rigidbody.hpp>

#include <LinearMath/btQuaternion.h>
#include <LinearMath/btVector3.h>
#include <glm/gtc/quaternion.hpp>

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

}  // namespace dawnforge::sim
