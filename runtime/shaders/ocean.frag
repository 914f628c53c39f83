#version 450 core
// Water: Fresnel between the water body and the sky's reflection, a sun glint, foam at
// the shore. Blended over what is behind it with depth writes on: the grid draws the
// rows lowest on screen first, so farther water behind nearer water fails the depth test
// and nothing needs sorting.
#include "common.glsl"
#include "ocean_block.glsl"
#include "ocean_waves.glsl"
in vec3 vWorld;
in vec3 vNormal;
in float vShore;
in vec3 vPlane;
layout(location = 0) uniform float ripples;  // 1 or 0 (scene "ocean.ripples")
layout(location = 0) out vec4 outColor;

// Ripples the grid is too coarse to carry: the slope of the noise height (ocean_waves.glsl's
// noiseHeight) per pixel, steepened RIPPLE_GAIN times, from its four channels at their own scale
// and once more at RIPPLE_FINE times the finest. The texture is mipmapped: where a pixel covers
// many texels the differences shrink, so far water keeps the grid's smooth normals, without moiré.
const float RIPPLE_GAIN = 6.0;
const float RIPPLE_FINE = 3.0;

vec2 channelSlope(vec2 xz, float t, int c, float times) {
    float scale = ocean.noiseScale[c] * times;
    vec2 uv = xz * scale + vec2(ocean.noiseDriftX[c], ocean.noiseDriftY[c]) * t * times;
    float e = 1.0 / float(textureSize(waveNoise, 0).x);
    vec2 dx = dFdx(uv), dy = dFdy(uv);  // the same footprint for the four taps
    float hx = textureGrad(waveNoise, uv + vec2(e, 0.0), dx, dy)[c] - textureGrad(waveNoise, uv - vec2(e, 0.0), dx, dy)[c];
    float hz = textureGrad(waveNoise, uv + vec2(0.0, e), dx, dy)[c] - textureGrad(waveNoise, uv - vec2(0.0, e), dx, dy)[c];
    return vec2(hx, hz) / (2.0 * e) * scale;  // per metre
}

vec2 rippleSlope(vec2 xz, float t) {
    vec2 slope = vec2(0.0);
    for (int c = 0; c < 4; ++c) slope += OCEAN_NOISE_WEIGHTS[c] * channelSlope(xz, t, c, 1.0);
    slope += OCEAN_NOISE_WEIGHTS[3] * channelSlope(xz, t, 3, RIPPLE_FINE);
    return ripples * RIPPLE_GAIN * ocean.params.z * slope;
}

void main() {
    vec3 n = normalize(vNormal);
    vec2 ripple = rippleSlope(vPlane.xy, frame.cameraPos.w) * vPlane.z;
    n = normalize(n - vec3(ripple.x, 0.0, ripple.y) * n.y);
    vec3 toFragment = vWorld - frame.cameraPos.xyz;
    float distance = length(toFragment);
    vec3 V = toFragment / max(distance, 1e-6);
    if (dot(n, -V) < 0.0) n = normalize(n + V * dot(n, V) * 1.01);  // back-facing slopes at grazing angles
    float cosTheta = clamp(dot(-V, n), 0.0, 1.0);
    float fresnel = 0.02 + 0.98 * pow(1.0 - cosTheta, 5.0);
    vec3 r = reflect(V, n);
    vec3 reflection = skyColor(r);
    vec3 glint = frame.sunColor.rgb * pow(max(dot(r, frame.sunDir.xyz), 0.0), 400.0) * 6.0;
    vec3 ambient = mix(frame.groundColor.rgb, frame.skyZenith.rgb, 0.7) + frame.sunColor.rgb * max(frame.sunDir.y, 0.0) * 0.3;
    vec3 body = mix(vec3(0.06, 0.22, 0.2), vec3(0.008, 0.05, 0.08), vShore) * ambient;
    float foam = (1.0 - smoothstep(0.0, 0.12, vShore)) * 0.5;
    vec3 color = mix(body, reflection, fresnel) + glint;
    color = mix(color, (frame.sunColor.rgb * max(frame.sunDir.y, 0.0) + ambient) * 0.8, foam);
    float alpha = clamp(mix(0.55, 0.95, smoothstep(0.0, 0.6, vShore)) + fresnel + foam, 0.0, 1.0);
    float haze = 1.0 - exp(-distance * 0.0009);
    outColor = vec4(mix(color, skyColor(V), haze * 0.85), alpha);
}
