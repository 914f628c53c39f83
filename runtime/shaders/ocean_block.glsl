// The Ocean uniform block (OceanUniforms in ocean_gpu.hpp) and the wave noise texture, as
// ocean.vert and ocean.frag read them.
layout(std140, binding = 2) uniform Ocean {
    vec4 waveDirs01;   // direction of waves 0 and 1 (x, z, x, z)
    vec4 waveDirs23;
    vec4 amplitude;
    vec4 wavelength;
    vec4 steepness;
    vec4 phase;
    vec4 noiseScale;
    vec4 noiseDriftX;
    vec4 noiseDriftY;
    vec4 params;       // level, shore depth, noise amplitude, grid columns
} ocean;
layout(binding = 5) uniform sampler2D waveNoise;  // mipmapped: the vertex shader reads level 0
