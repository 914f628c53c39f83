#pragma once
// The Ocean uniform block shared by ocean.vert and gpu_checks.comp (std140, vec4 only).
#include <dawnforge/runtime/ocean.hpp>

#include "gl.hpp"

#include <glm/glm.hpp>

namespace dawnforge::runtime {

struct OceanUniforms {
    glm::vec4 waveDirs01, waveDirs23, amplitude, wavelength, steepness, phase, noiseScale, noiseDriftX, noiseDriftY, params;
};

// The block from the one packing of the waves (packForGpu, which ocean_waves.glsl documents),
// plus the water level, the shore depth and the grid's column count.
inline OceanUniforms oceanUniforms(const WaveSet& waves, double level, double shoreDepth, int columns) {
    const OceanWavesGpu g = packForGpu(waves);
    const auto v = [](const std::array<float, 4>& a) { return glm::vec4(a[0], a[1], a[2], a[3]); };
    return {v(g.dirs01),     v(g.dirs23),      v(g.amplitude),   v(g.wavelength),  v(g.steepness),
            v(g.phase),      v(g.noiseScale),  v(g.noiseDriftX), v(g.noiseDriftY),
            glm::vec4(float(level), float(shoreDepth), g.noiseAmplitude, float(columns))};
}

// The noise texture: RGBA32F, GL_REPEAT, with its mip chain for ocean.frag's ripples (the vertex
// shader and gpu_checks.comp read level 0, GL_LINEAR).
inline gl::Texture uploadWaveNoise(const WaveNoise& noise) {
    int levels = 1;
    while ((noise.size >> levels) > 0) ++levels;
    gl::Texture t = gl::makeTexture2D(GL_RGBA32F, noise.size, noise.size, levels, GL_LINEAR_MIPMAP_LINEAR, GL_LINEAR, GL_REPEAT);
    glTextureSubImage2D(t.id(), 0, 0, 0, noise.size, noise.size, GL_RGBA, GL_FLOAT, noise.rgba.data());
    glGenerateTextureMipmap(t.id());
    return t;
}

}  // namespace dawnforge::runtime
