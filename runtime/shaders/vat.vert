#version 450 core
// Rigid-body VAT playback (native preset: metres, +Y up). Piece j's texel at frame k is
// (column j mod W, row k·R + floor(j / W)); the lookup UV (TEXCOORD_1) holds frame 0's
// texel centre. Position RGB = pivot, A = 0.25 × dropped quaternion component; rotation
// RGB = the other three components, A = signed turns to the next frame. Nearest texels
// (texelFetch), interpolated between frames along the turn count.
#define DAWNFORGE_VERTEX_STAGE
#include "common.glsl"
#include "atlas.glsl"
#include "surface.glsl"
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec2 aUv0;
layout(location = 3) in vec2 aLookup;
layout(location = 4) in vec2 aPivotX;   // (px, 0)
layout(location = 8) in vec2 aPivotYZ;  // (py, pz)
layout(location = 5) in uint aMaterial;
layout(location = 6) in uvec4 aBlocks;
layout(location = 7) in uint aBuilding;
layout(binding = 3) uniform sampler2D vatPosition;
layout(binding = 4) uniform sampler2D vatRotation;
layout(location = 0) uniform mat4 depthViewProj;
layout(location = 1) uniform vec4 vatLayout;  // W, R, height, frames
layout(location = 2) uniform float vatFrame;  // continuous frame number, clamped by the caller
layout(location = 3) uniform mat4 model;      // placement of the instance

vec4 unpackRotation(vec3 t, int dropped) {
    float r = sqrt(max(0.0, 1.0 - dot(t, t)));
    if (dropped == 0) return vec4(t, r);                  // (x, y, z, w)
    if (dropped == 1) return vec4(r, t.y, t.z, t.x);
    if (dropped == 2) return vec4(t.x, r, t.z, t.y);
    return vec4(t.x, t.y, r, t.z);
}
vec4 quatMul(vec4 a, vec4 b) {
    return vec4(a.w * b.xyz + b.w * a.xyz + cross(a.xyz, b.xyz), a.w * b.w - dot(a.xyz, b.xyz));
}
vec3 rotate(vec4 q, vec3 v) {
    vec3 t = 2.0 * cross(q.xyz, v);
    return v + q.w * t + cross(q.xyz, t);
}

void main() {
    int W = int(vatLayout.x), R = int(vatLayout.y), height = int(vatLayout.z), frames = int(vatLayout.w);
    ivec2 texel = ivec2(int(aLookup.x * float(W)), int(aLookup.y * float(height)));
    float f = clamp(vatFrame, 0.0, float(frames - 1));
    int k0 = int(floor(f));
    int k1 = min(k0 + 1, frames - 1);
    float a = f - float(k0);
    vec4 p0 = texelFetch(vatPosition, texel + ivec2(0, k0 * R), 0);
    vec4 p1 = texelFetch(vatPosition, texel + ivec2(0, k1 * R), 0);
    vec4 r0 = texelFetch(vatRotation, texel + ivec2(0, k0 * R), 0);
    vec4 r1 = texelFetch(vatRotation, texel + ivec2(0, k1 * R), 0);
    vec4 q0 = unpackRotation(r0.xyz, int(floor(4.0 * p0.a + 0.5)));
    vec4 q1 = unpackRotation(r1.xyz, int(floor(4.0 * p1.a + 0.5)));
    // Turns: negative means go to −q1; the angle is 2π·|turns|, so more than half a turn
    // per frame interpolates the right way round.
    float turns = r0.a;
    vec4 q = q0;
    if (turns != 0.0 && a > 0.0) {
        if (turns < 0.0) q1 = -q1;
        vec4 delta = quatMul(q1, vec4(-q0.xyz, q0.w));
        float s = length(delta.xyz);
        if (s > 1e-7) {
            float half_ = a * kPi * abs(turns);
            q = quatMul(vec4(delta.xyz / s * sin(half_), cos(half_)), q0);
        }
    }
    vec3 pivot = vec3(aPivotX.x, aPivotYZ.x, aPivotYZ.y);
    vec3 local = mix(p0.xyz, p1.xyz, a) + rotate(q, aPosition - pivot);
    vec3 world = (model * vec4(local, 1.0)).xyz;
#ifdef DEPTH_PASS
    gl_Position = depthViewProj * vec4(world, 1.0);
#else
    vWorld = world;
    vNormal = mat3(model) * rotate(q, aNormal);
    vLight = vec3(0.0, 0.0, -1.0);  // pieces are not baked
    vUv0 = aUv0;
    vUv1 = vec2(0.0);
    vUv2 = vec2(0.0);
    vMaterial = aMaterial & 15u;
    vRect = atlasBlockRect(blockCode(aBlocks, vMaterial));
    vTile = materials.tileMetres[vMaterial].x;
    vBuilding = aBuilding;
    gl_Position = frame.viewProj * vec4(world, 1.0);
#endif
}
