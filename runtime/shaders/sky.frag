#version 450 core
#include "common.glsl"
in vec2 vNdc;
layout(location = 0) out vec4 outColor;
void main() {
    vec4 far = frame.invViewProj * vec4(vNdc, 1.0, 1.0);
    vec4 near = frame.invViewProj * vec4(vNdc, -1.0, 1.0);
    vec3 dir = normalize(far.xyz / far.w - near.xyz / near.w);
    outColor = vec4(skyColor(dir) + sunDisk(dir), 1.0);
}
