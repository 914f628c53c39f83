#pragma once
// The Ocean uniform block shared by ocean.vert and gpu_checks.comp (std140, vec4 only).
#include <dawnforge/runtime/ocean.hpp>

#include "gl.hpp"

#include <glm/glm.hpp>

namespace dawnforge::runtime {

// The Ocean uniform block of ocean.vert (std140, vec4 only).
struct OceanUniforms {
    glm::vec4 waveDirs01, waveDirs23, amplitude, wavelength, steepness, phase, noiseScale, noiseDriftX, noiseDriftY, params;
};

inline OceanUniforms oceanUniforms(const WaveSet& waves, double level, double shoreDepth, int columns) {
    OceanUniforms u{};
    for (int i = 0; i < 4; ++i) {
        const GerstnerWave& w = waves.waves[std::size_t(i)];
        glm::vec4& dirs = i < 2 ? u.waveDirs01 : u.waveDirs23;
        dirs[(i % 2) * 2] = float(w.direction.x);
        dirs[(i % 2) * 2 + 1] = float(w.direction.y);
        u.amplitude[i] = float(w.amplitude);
        u.wavelength[i] = float(w.wavelength);
        u.steepness[i] = float(w.steepness);
        u.phase[i] = float(w.phase);
        u.noiseScale[i] = float(waves.noiseScale[std::size_t(i)]);
        u.noiseDriftX[i] = float(waves.noiseDrift[std::size_t(i)].x);
        u.noiseDriftY[i] = float(waves.noiseDrift[std::size_t(i)].y);
    }
    u.params = glm::vec4(float(level), float(shoreDepth), float(waves.noiseAmplitude), float(columns));
    return u;
}

// The noise texture as the vertex shader samples it: RGBA32F, GL_LINEAR, GL_REPEAT, one level.
inline gl::Texture uploadWaveNoise(const WaveNoise& noise) {
    gl::Texture t = gl::makeTexture2D(GL_RGBA32F, noise.size, noise.size, 1, GL_LINEAR, GL_LINEAR, GL_REPEAT);
    glTextureSubImage2D(t.id(), 0, 0, 0, noise.size, noise.size, GL_RGBA, GL_FLOAT, noise.rgba.data());
    return t;
}

}  // namespace dawnforge::runtime
