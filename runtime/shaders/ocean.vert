#version 450 core
// Projected-grid ocean: each vertex is a fixed (column, row) of a screen-space grid whose
// rows the CPU places every frame (ocean.hpp: squeezed below the horizon, geometric in
// distance, a virtual camera for grazing views). The vertex is the camera ray through its
// NDC point cut by the water plane, displaced by four Gerstner waves and the noise texture,
// with the amplitude attenuated near shores from the overlook depth texture.
#include "common.glsl"
#include "ocean_waves.glsl"
layout(location = 0) in vec2 aGrid;  // (column / (columns − 1), row)
layout(std430, binding = 1) readonly buffer Rows { float rowNdcY[]; };
#include "ocean_block.glsl"
out vec3 vWorld;
out vec3 vNormal;
out float vShore;  // 0 at the shore, 1 in open water
out vec3 vPlane;   // world x, z of the undisplaced point (the waves' phase space) and the waves' attenuation

float shoreAttenuation(vec2 xz) {
    float ground = overlookHeight(xz);
    if (ground < -1e8) return 1.0;
    return smoothstep(0.0, ocean.params.y, ocean.params.x - ground);
}

void main() {
    float level = ocean.params.x;
    vec2 ndc = vec2(aGrid.x * 2.0 - 1.0, rowNdcY[int(aGrid.y + 0.5)]);
    vec3 p0 = oceanGridVertex(ndc, frame.invViewProj, level);
    float shore = shoreAttenuation(p0.xz);
    // The grid's outer rows and columns lie on the screen's edges: they keep still so the
    // waves never pull the water's edge into view.
    float column = aGrid.x * (ocean.params.w - 1.0);
    float edge = min(smoothstep(0.0, 3.0, aGrid.y), min(smoothstep(0.0, 2.0, column), smoothstep(0.0, 2.0, ocean.params.w - 1.0 - column)));
    float attenuation = shore * edge;
    vec3 normal;
    vec2 phaseXz = p0.xz + frame.origin.xz;  // world x, z (modulo 8192 m): waves stay put as the render origin moves
    vec3 d = gerstnerDisplacement(phaseXz, frame.cameraPos.w, attenuation, ocean.waveDirs01, ocean.waveDirs23,
                                  ocean.amplitude, ocean.wavelength, ocean.steepness, ocean.phase, normal);
    float detail = noiseHeight(waveNoise, phaseXz, frame.cameraPos.w, ocean.params.z, ocean.noiseScale,
                               ocean.noiseDriftX, ocean.noiseDriftY, attenuation);
    vWorld = vec3(p0.x + d.x, level + d.y + detail, p0.z + d.z);
    vNormal = normal;
    vShore = shore;
    vPlane = vec3(phaseXz, attenuation);
    gl_Position = frame.viewProj * vec4(vWorld, 1.0);
}
