// Shared by every pass: the per-frame uniform block, sky colour, sun shadow and lighting.
layout(std140, binding = 0) uniform Frame {
    mat4 viewProj;
    mat4 invViewProj;
    mat4 lightViewProj;
    vec4 cameraPos;    // xyz; w = scene time (s)
    vec4 sunDir;       // xyz towards the sun; w = night (0 day, 1 night)
    vec4 sunColor;     // linear rgb; w = shadow depth bias (0.2 m in the light's depth units)
    vec4 skyZenith;
    vec4 skyHorizon;
    vec4 groundColor;
    vec4 viewport;     // width, height, 1/width, 1/height
    vec4 overlook;     // xz origin of the overlook area, xz size
    vec4 overlookDepth;// camera height, near, far - near, 0
    vec4 origin;       // the render origin's x, y, z (x and z modulo 8192 m): positions here are less it
} frame;

const float kPi = 3.14159265;

vec3 skyColor(vec3 dir) {
    float up = clamp(dir.y, -1.0, 1.0);
    vec3 sky = mix(frame.skyHorizon.rgb, frame.skyZenith.rgb, pow(clamp(up, 0.0, 1.0), 0.55));
    // Below the horizon: the horizon colour fading to a darker haze.
    sky = up < 0.0 ? mix(frame.skyHorizon.rgb, frame.groundColor.rgb, clamp(-up * 3.0, 0.0, 1.0)) : sky;
    float sunAmount = max(dot(dir, frame.sunDir.xyz), 0.0);
    sky += frame.sunColor.rgb * (0.35 * pow(sunAmount, 8.0) + 0.25 * pow(sunAmount, 64.0));
    return sky;
}

// Sun (or moon) disk, added by the sky pass only.
vec3 sunDisk(vec3 dir) {
    float d = dot(dir, frame.sunDir.xyz);
    return frame.sunColor.rgb * 12.0 * smoothstep(0.9995, 0.9998, d);
}

layout(binding = 7) uniform sampler2DShadow shadowMap;

// The shadow map's coordinates of a point lifted along its normal by 0.15 m or one shadow texel,
// whichever is more: a texel of a large scene's map spans more depth on a sloped surface than the
// fixed bias covers (acne: stripes that alias into rings far off); z > 1: outside the map.
vec3 shadowCoord(vec3 worldPos, vec3 normal) {
    mat4 m = frame.lightViewProj;
    float texelMetres = 2.0 / (length(vec3(m[0][0], m[1][0], m[2][0])) * float(textureSize(shadowMap, 0).x));
    vec4 p = m * vec4(worldPos + normal * max(0.15, texelMetres), 1.0);
    vec3 q = p.xyz / p.w * 0.5 + 0.5;
    bool outside = any(lessThan(q.xy, vec2(0.0))) || any(greaterThan(q.xy, vec2(1.0))) || q.z > 1.0;
    return outside ? vec3(0.5, 0.5, 2.0) : vec3(q.xy, q.z - frame.sunColor.w);
}

// 4 taps, each a bilinear comparison (2 × 2 PCF).
float sunShadow(vec3 worldPos, vec3 normal) {
    vec3 q = shadowCoord(worldPos, normal);
    if (q.z > 1.5) return 1.0;
    vec2 texel = 1.0 / vec2(textureSize(shadowMap, 0));
    float sum = 0.0;
    for (int i = 0; i < 4; ++i) sum += texture(shadowMap, vec3(q.xy + (vec2(i & 1, i >> 1) - 0.5) * texel, q.z));
    return sum * 0.25;
}

// One bilinear comparison: what the probes' 64-pixel faces need.
float sunShadowCoarse(vec3 worldPos, vec3 normal) {
    vec3 q = shadowCoord(worldPos, normal);
    return q.z > 1.5 ? 1.0 : texture(shadowMap, q);
}

// The sky/ground hemisphere's light on an open surface of normal n (no occlusion).
vec3 hemisphereLight(vec3 n) {
    return mix(frame.groundColor.rgb, 0.5 * (frame.skyZenith.rgb + frame.skyHorizon.rgb), n.y * 0.5 + 0.5) * 0.9;
}

#include "probe_light.glsl"

// Light that is not the direct sun: the probes' irradiance / π where probes are near (the
// renderer's light unit: an open sky gives the hemisphere term's 0.45 (zenith + horizon)), the
// sky/ground hemisphere elsewhere, blended where the probes thin out.
vec3 ambientLight(vec3 worldPos, vec3 n) {
    vec4 probe = probeIrradiance(worldPos, n);
    return mix(hemisphereLight(n), probe.rgb / kPi, clamp(probe.w * 4.0, 0.0, 1.0));
}

// Diffuse light on a surface: the sun with its shadow plus the ambient light.
vec3 diffuseLight(vec3 worldPos, vec3 n) {
    float ndl = max(dot(n, frame.sunDir.xyz), 0.0);
    float shadow = ndl > 0.0 ? sunShadow(worldPos, n) : 0.0;
    return frame.sunColor.rgb * ndl * shadow + ambientLight(worldPos, n);
}

// Baked lighting (bake/lighting.hpp, CITY_DIR/bake/): R sky, G sun bounce averaged over the
// day, B ambient occlusion, A lamps; stored s decodes to s² × range.
const vec4 kBakedRange = vec4(2.0, 2.0, 1.0, 4.0);
// Ceiling lamps' colour (linear): warm white, scaled by the night factor like the lit windows.
const vec3 kLampColor = vec3(1.0, 0.74, 0.46);
vec4 decodeBaked(vec4 stored) { return stored * stored * kBakedRange; }

// The sky's irradiance on an open horizontal surface (baked R = 1 there), the same sky as the
// unbaked hemisphere term of diffuseLight().
vec3 bakedSkyColor() { return 0.45 * (frame.skyZenith.rgb + frame.skyHorizon.rgb); }

// Light of the baked channels without the direct sun: sky, sun bounce and lamps (the issue's
// skyColour(t) × R + sunColour(t) × G + lampColour × A × night(t)).
vec3 bakedIndirect(vec4 b) {
    return bakedSkyColor() * b.r + frame.sunColor.rgb * b.g + kLampColor * b.a * frame.sunDir.w;
}

// Diffuse light on a baked surface: (sun × shadow + the baked terms) × AO.
vec3 bakedDiffuseLight(vec3 worldPos, vec3 n, vec4 b) {
    float ndl = max(dot(n, frame.sunDir.xyz), 0.0);
    float shadow = ndl > 0.0 ? sunShadow(worldPos, n) : 0.0;
    return (frame.sunColor.rgb * ndl * shadow + bakedIndirect(b)) * b.b;
}
