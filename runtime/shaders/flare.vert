#version 450 core
// Lens flares (runtime/src/flares.hpp): one instance per (light, element). The light is
// projected, its visibility measured from the scene's depth at 32 points of a disc around
// it (this frame's depth: no query, no lag), and the element placed on the line from the
// light through the screen centre, scaled by visibility and faded towards the screen edge.
#include "common.glsl"

layout(location = 0) in vec4 iLight;    // xyz position (w = 1) or direction (w = 0)
layout(location = 1) in vec4 iColour;   // rgb; w: the light's radius (m, or radians for a direction)
layout(location = 2) in vec4 iElement;  // axis (1 light, 0 centre), size (of screen height), shape, falloff (m)

layout(binding = 0) uniform sampler2D sceneDepth;    // GL_DEPTH_COMPONENT32F, not attached to the target
layout(location = 0) uniform vec4 lens;              // near, far, projection[1][1], unused

out vec2 vUv;
out vec3 vColour;
flat out int vShape;

float viewDistance(float depth) {
    float n = lens.x, f = lens.y;
    return 2.0 * n * f / ((f + n) - (depth * 2.0 - 1.0) * (f - n));
}

// The share of 32 depth samples (a 6 × 6 grid less its corners, symmetric about the
// centre: an edge through the light hides exactly half) that do not hide the light.
// Samples off the screen count as hidden, so a flare fades as its light leaves the view.
float visibility(vec2 pixel, float radius, float lightDistance, bool directional) {
    ivec2 size = ivec2(frame.viewport.xy);
    float spacing = radius / 2.5, visible = 0.0;
    for (int j = 0; j < 6; ++j)
        for (int i = 0; i < 6; ++i) {
            vec2 o = vec2(i, j) - 2.5;
            if (dot(o, o) > 9.0) continue;
            ivec2 p = ivec2(floor(pixel + o * spacing));
            if (any(lessThan(p, ivec2(0))) || any(greaterThanEqual(p, size))) continue;
            float d = texelFetch(sceneDepth, p, 0).r;
            // The sun shows where nothing was drawn; a point where nothing is nearer than it
            // (less a margin for the lamp's own shade).
            visible += directional ? step(1.0, d) : step(lightDistance - 0.5 - 0.01 * lightDistance, viewDistance(d));
        }
    return visible / 32.0;
}

void main() {
    vec2 corner = vec2(gl_VertexID & 1, gl_VertexID >> 1) * 2.0 - 1.0;  // a strip of 4
    vUv = corner;
    vShape = int(iElement.z);
    gl_Position = vec4(-2.0, -2.0, -2.0, 1.0);  // hidden: every corner here, degenerate triangles
    vColour = vec3(0.0);

    bool directional = iLight.w == 0.0;
    vec4 clip = frame.viewProj * iLight;
    if (clip.w <= 0.0) return;  // behind the camera
    vec2 ndc = clip.xy / clip.w;
    float edge = 1.0 - smoothstep(0.85, 1.05, max(abs(ndc.x), abs(ndc.y)));
    float falloff = iElement.w > 0.0 ? min(1.0, pow(iElement.w / clip.w, 2.0)) : 1.0;
    // Off the screen, or too faint to change a pixel of the tonemapped image: nothing to draw.
    if (edge <= 0.0 || max(max(iColour.r, iColour.g), iColour.b) * falloff < 5e-4) return;
    vec2 pixel = (ndc * 0.5 + 0.5) * frame.viewport.xy;
    float pixelsPerUnit = 0.5 * frame.viewport.y * lens.z;  // per radian, or per metre at distance 1
    float radius = clamp(iColour.w * pixelsPerUnit / (directional ? 1.0 : clip.w), 2.0, 64.0);
    float v = visibility(pixel, radius, clip.w, directional);
    if (v <= 0.0) return;
    vColour = iColour.rgb * v * falloff * edge;
    vec2 centre = ndc * iElement.x;
    vec2 extent = 2.0 * iElement.y * vec2(frame.viewport.y * frame.viewport.z, 1.0);
    gl_Position = vec4(centre + corner * extent, 0.0, 1.0);
}
