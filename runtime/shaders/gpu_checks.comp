#version 450 core
// Evaluates the vertex shaders' functions for a list of inputs, so tests can compare the
// GPU with the CPU (ocean.cpp): mode 0 = waves at plane points, mode 1 = grid vertices,
// mode 2 = tree-space points bent by the wind (wind.glsl, Pivot Painter textures bound),
// mode 3 = probe arithmetic (probes.glsl) for directions.
#include "ocean_waves.glsl"
#include "probes.glsl"
#include "wind.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Inputs { vec4 inputs[]; };
layout(std430, binding = 1) writeonly buffer Outputs { vec4 outputs[]; };
layout(std140, binding = 2) uniform Ocean {
    vec4 waveDirs01, waveDirs23, amplitude, wavelength, steepness, phase, noiseScale, noiseDriftX, noiseDriftY, params;
} ocean;
layout(binding = 5) uniform sampler2D waveNoise;
layout(location = 0) uniform int mode;
layout(location = 1) uniform int count;
layout(location = 2) uniform mat4 inverseViewProjection;
layout(location = 3) uniform vec4 windDirSpeed;  // mode 2: unit wind direction (tree space), speed (m/s)
layout(std430, binding = 3) readonly buffer Probe { vec4 probeSh[9]; vec4 probeCube[6]; };  // mode 3
void main() {
    int i = int(gl_GlobalInvocationID.x);
    if (i >= count) return;
    vec4 in_ = inputs[i];
    if (mode == 0) {  // in: (x, z, t, attenuation); out: displaced point relative to (x, level, z), noise height in w
        vec3 normal;
        vec3 d = gerstnerDisplacement(in_.xy, in_.z, in_.w, ocean.waveDirs01, ocean.waveDirs23, ocean.amplitude,
                                      ocean.wavelength, ocean.steepness, ocean.phase, normal);
        float h = noiseHeight(waveNoise, in_.xy, in_.z, ocean.params.z, ocean.noiseScale, ocean.noiseDriftX,
                              ocean.noiseDriftY, in_.w);
        outputs[2 * i] = vec4(d, h);
        outputs[2 * i + 1] = vec4(normal, 0.0);
    } else if (mode == 2) {  // in: (point, phase), (uv1, time, 0); out: the bent point, its bent normal (0, 1, 0)
        vec3 p = in_.xyz, n = vec3(0.0, 1.0, 0.0);
        vec4 in2 = inputs[i + count];
        windBend(p, n, in2.xy, windDirSpeed.xyz, windDirSpeed.w, in2.z, in_.w);
        outputs[2 * i] = vec4(p, 1.0);
        outputs[2 * i + 1] = vec4(n, 0.0);
    } else if (mode == 3) {  // in: (unit direction, distance); out: (SH irradiance, chebyshev), (ambient irradiance, 0),
                             // (octEncode, 0, 0), (octDecode(octEncode), 0) over four outputs per input
        vec3 c[9];
        for (int k = 0; k < 9; ++k) c[k] = probeSh[k].rgb;
        vec3 cube[6];
        for (int k = 0; k < 6; ++k) cube[k] = probeCube[k].rgb;
        vec3 d = in_.xyz;
        outputs[2 * i] = vec4(shIrradiance(c, d), chebyshevVisibility(in_.w, 2.0, 4.5));
        vec2 e = octEncode(d);
        outputs[2 * i + 1] = vec4(ambientIrradiance(cube, d).r, e, octDecode(e).y);
    } else {          // in: (ndc x, ndc y, level, 0); out: the grid vertex
        outputs[2 * i] = vec4(oceanGridVertex(in_.xy, inverseViewProjection, in_.z), 1.0);
        outputs[2 * i + 1] = vec4(0.0);
    }
}
