#version 450 core
// A probe's sphere: a white (0.8) diffuse surface lit by that probe alone.
#include "common.glsl"
in vec3 vNormal;
flat in int vSlot;
layout(location = 0) out vec4 outColor;

void main() {
    outColor = vec4(0.8 * probeTileIrradiance(vSlot, normalize(vNormal)).rgb / kPi, 1.0);
}
