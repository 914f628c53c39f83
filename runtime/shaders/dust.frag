#version 450 core
// A dust puff: a soft round sprite, its opacity falling from the centre, faded where it meets
// the scene (its distance behind the sprite against half the puff's radius: soft particles),
// blended over the HDR image.
#include "common.glsl"

layout(binding = 12) uniform sampler2D sceneDepth;
layout(location = 0) uniform vec4 lens;  // near, far, projection[1][1], unused

in vec2 vCorner;
in float vOpacity;
in float vRadius;
in vec3 vLight;
out vec4 outColor;

const vec3 kDustAlbedo = vec3(0.62, 0.58, 0.52);

float viewDistance(float depth) {
    float n = lens.x, f = lens.y;
    return 2.0 * n * f / ((f + n) - (depth * 2.0 - 1.0) * (f - n));
}

void main() {
    float r2 = dot(vCorner, vCorner);
    if (r2 >= 1.0) discard;
    float shape = (1.0 - r2) * (1.0 - r2);
    float behind = viewDistance(texelFetch(sceneDepth, ivec2(gl_FragCoord.xy), 0).r) - viewDistance(gl_FragCoord.z);
    float soft = clamp(behind / max(0.5 * vRadius, 0.05), 0.0, 1.0);
    float alpha = vOpacity * shape * soft;
    if (alpha <= 0.0) discard;
    outColor = vec4(kDustAlbedo * vLight, alpha);
}
