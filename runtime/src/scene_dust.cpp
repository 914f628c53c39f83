// The destructions' dust (SceneGpu::drawDust): one instanced draw per VAT that has dust, six
// vertices a puff (runtime/shaders/dust.vert), blended over the HDR image after the ocean.
// Puffs are not sorted: they are all one colour of dust, so the order of two overlapping
// puffs changes little.
#include "scene_gpu.hpp"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>

namespace dawnforge::runtime {

std::size_t SceneGpu::drawDust(double time, GLuint depth, glm::vec4 lens, FrameStats& stats) {
    std::size_t draws = 0;
    for (const Vat& v : vats_) {
        if (v.dustLayout.w <= 0.0f || time < v.startTime) continue;
        if (draws == 0) {
            glUseProgram(dust_.id());
            glUniform4fv(0, 1, glm::value_ptr(lens));
            glBindTextureUnit(12, depth);
            glDisable(GL_DEPTH_TEST);
            glDepthMask(GL_FALSE);
            glEnable(GL_BLEND);
            glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
            glBindVertexArray(emptyVao_.id());
        }
        glBindTextureUnit(3, v.dust.id());
        glUniform4fv(1, 1, glm::value_ptr(v.dustLayout));
        setPlayback(v, time);
        glDrawArraysInstanced(GL_TRIANGLES, 0, 6, GLsizei(v.dustLayout.w));
        stats.triangles += 2 * std::size_t(v.dustLayout.w);
        ++draws;
    }
    if (draws > 0) {
        glDisable(GL_BLEND);
        glDepthMask(GL_TRUE);
        glEnable(GL_DEPTH_TEST);
    }
    return draws;
}

}  // namespace dawnforge::runtime
