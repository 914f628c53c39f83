#version 450 core
// Probe capture, step 2: one instanced draw per cube face of a probe, 36 vertices per box
// (made here from gl_VertexID), the instances read from the face's list of visible boxes.
#include "probe_box.glsl"
layout(std430, binding = 1) readonly buffer Visible { uint visible[]; };
layout(location = 0) uniform mat4 viewProj;
layout(location = 1) uniform uint listStart;  // the face's list in Visible
out vec3 vWorld;
flat out vec3 vNormal;
flat out vec3 vAlbedo;

void main() {
    ProxyBox b = boxes[visible[listStart + uint(gl_InstanceID)]];
    int face = gl_VertexID / 6, corner = gl_VertexID % 6;
    const vec2 quad[6] = vec2[6](vec2(-1, -1), vec2(1, -1), vec2(1, 1), vec2(-1, -1), vec2(1, 1), vec2(-1, 1));
    int axis = face / 2;
    float side = (face & 1) == 0 ? 1.0 : -1.0;
    vec3 l = axis == 0 ? vec3(side, quad[corner]) : axis == 1 ? vec3(quad[corner].x, side, quad[corner].y)
                                                               : vec3(quad[corner], side);
    vec3 axes[3] = vec3[3](b.u.xyz, b.up.xyz, b.w.xyz);
    vec3 extent = vec3(b.u.w, b.up.w, b.w.w);
    vWorld = b.centre.xyz + axes[0] * l.x * extent.x + axes[1] * l.y * extent.y + axes[2] * l.z * extent.z;
    vNormal = side * axes[axis];
    vAlbedo = b.colours[face].rgb;
    gl_Position = viewProj * vec4(vWorld, 1.0);
}
