#pragma once
// Frustum culling of axis-aligned boxes (private to the runtime), in float (the GPU's render
// space) or double (a world's runtime coordinates).
#include <glm/glm.hpp>

namespace dawnforge::runtime {

// Is the box [lo, hi] outside one of the six planes of `viewProj` (OpenGL clip space)?
template <class T, glm::qualifier Q>
bool outsideFrustum(const glm::mat<4, 4, T, Q>& viewProj, glm::vec<3, T, Q> lo, glm::vec<3, T, Q> hi) {
    const glm::mat<4, 4, T, Q> m = glm::transpose(viewProj);
    const glm::vec<4, T, Q> planes[6] = {m[3] + m[0], m[3] - m[0], m[3] + m[1], m[3] - m[1], m[3] + m[2], m[3] - m[2]};
    for (const glm::vec<4, T, Q>& p : planes) {
        const glm::vec<3, T, Q> far(p.x > 0 ? hi.x : lo.x, p.y > 0 ? hi.y : lo.y, p.z > 0 ? hi.z : lo.z);
        if (glm::dot(glm::vec<3, T, Q>(p), far) + p.w < T(0)) return true;
    }
    return false;
}

}  // namespace dawnforge::runtime
