#version 450 core
// Probe capture, step 1: the proxy boxes each face of each probe of the batch sees. One
// invocation per (box, probe): a box within reach whose bounding sphere touches a face's 90°
// frustum is appended to that face's list, and the face's indirect draw counts it.
#include "probe_box.glsl"
layout(local_size_x = 64) in;
layout(std430, binding = 1) writeonly buffer Visible { uint visible[]; };
// DrawArraysIndirectCommand per (probe, face): count (36), instanceCount, first, baseInstance.
layout(std430, binding = 2) buffer Commands { uint commands[]; };
layout(std430, binding = 3) readonly buffer Batch { vec4 batch[]; };  // xyz: probe position
layout(location = 0) uniform uint boxCount;
layout(location = 1) uniform float reach;
layout(location = 2) uniform uint listSize;  // each face's list holds up to this many boxes

void main() {
    uint box = gl_GlobalInvocationID.x, probe = gl_WorkGroupID.y;
    if (box >= boxCount) return;
    ProxyBox b = boxes[box];
    vec3 d = b.centre.xyz - batch[probe].xyz;
    float r = length(vec3(b.u.w, b.up.w, b.w.w));
    if (length(d) - r > reach) return;
    for (int f = 0; f < 6; ++f) {
        vec3 a = kFaceForward[f], up = kFaceUp[f], right = cross(a, up);
        const float s = 0.70710678;
        bool seen = dot(d, a) > -r && dot(d, (a - right) * s) > -r && dot(d, (a + right) * s) > -r &&
                    dot(d, (a - up) * s) > -r && dot(d, (a + up) * s) > -r;
        if (!seen) continue;
        uint face = probe * 6u + uint(f);
        uint slot = atomicAdd(commands[face * 4u + 1u], 1u);
        visible[face * listSize + slot] = box;
    }
}
