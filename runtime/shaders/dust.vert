#version 450 core
// Dust puffs (a VAT's _dust.exr, exporters/src/vat_dust.cpp): one instance per puff, six
// vertices of a camera-facing square. Puff p's texel at frame k: (p mod W, k·R + floor(p / W))
// holds its centre (RGB) and diameter (A); (p mod W, (frames + k)·R + floor(p / W)).r its
// opacity; both interpolated between frames. Lit once per puff at its centre: the sun through
// the shadow map, forward-scattered a little, and the sky's hemisphere light.
#include "common.glsl"

layout(binding = 3) uniform sampler2D dustTexture;
layout(location = 1) uniform vec4 dustLayout;  // W, R, frames, puffs
layout(location = 2) uniform float dustFrame;  // continuous frame number
layout(location = 3) uniform mat4 model;       // placement of the instance

out vec2 vCorner;
out float vOpacity;
out float vRadius;
out vec3 vLight;

const vec2 kCorners[6] = vec2[](vec2(-1, -1), vec2(1, -1), vec2(1, 1), vec2(-1, -1), vec2(1, 1), vec2(-1, 1));

void main() {
    int W = int(dustLayout.x), R = int(dustLayout.y), frames = int(dustLayout.z);
    int puff = gl_InstanceID;
    ivec2 texel = ivec2(puff % W, puff / W);
    float f = clamp(dustFrame, 0.0, float(frames - 1));
    int k0 = int(floor(f));
    int k1 = min(k0 + 1, frames - 1);
    float a = f - float(k0);
    vec4 p = mix(texelFetch(dustTexture, texel + ivec2(0, k0 * R), 0), texelFetch(dustTexture, texel + ivec2(0, k1 * R), 0), a);
    float opacity = mix(texelFetch(dustTexture, texel + ivec2(0, (frames + k0) * R), 0).r,
                        texelFetch(dustTexture, texel + ivec2(0, (frames + k1) * R), 0).r, a);
    vec3 centre = (model * vec4(p.xyz, 1.0)).xyz;
    float radius = 0.5 * p.w * length(model[0].xyz);
    vec3 view = centre - frame.cameraPos.xyz;
    if (opacity <= 0.0 || radius <= 0.0 || length(view) < 1e-3) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0);  // outside the clip volume: nothing drawn
        return;
    }
    vec3 forward = normalize(view);
    vec3 right = abs(forward.y) < 0.999 ? normalize(cross(forward, vec3(0.0, 1.0, 0.0))) : vec3(1.0, 0.0, 0.0);
    vec3 up = cross(right, forward);
    vCorner = kCorners[gl_VertexID];
    gl_Position = frame.viewProj * vec4(centre + (vCorner.x * right + vCorner.y * up) * radius, 1.0);
    vOpacity = opacity;
    vRadius = radius;
    float sun = sunShadowCoarse(centre, vec3(0.0, 1.0, 0.0));
    float forwardScatter = 0.6 + 0.4 * max(dot(forward, frame.sunDir.xyz), 0.0);
    vLight = frame.sunColor.rgb * max(frame.sunDir.y, 0.0) * sun * forwardScatter + hemisphereLight(vec3(0.0, 1.0, 0.0));
}
