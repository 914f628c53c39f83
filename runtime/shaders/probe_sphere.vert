#version 450 core
// The probes' debug view: a small sphere at every injected probe, shaded by its irradiance.
#include "common.glsl"
layout(std430, binding = 6) readonly buffer SphereVertices { vec4 sphere[]; };  // unit, a triangle list
layout(std430, binding = 7) readonly buffer Shown { vec4 shown[]; };           // xyz: probe; w: cache slot
layout(location = 0) uniform float radius;
out vec3 vNormal;
flat out int vSlot;

void main() {
    vec3 n = sphere[gl_VertexID].xyz;
    vec4 probe = shown[gl_InstanceID];
    vNormal = n;
    vSlot = int(probe.w);
    gl_Position = frame.viewProj * vec4(probe.xyz + n * radius, 1.0);
}
