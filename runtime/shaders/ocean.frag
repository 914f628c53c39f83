#version 450 core
// Water: Fresnel between the water body and the sky's reflection, a sun glint, foam at
// the shore. Blended over what is behind it with depth writes on: the grid draws the
// rows lowest on screen first, so farther water behind nearer water fails the depth test
// and nothing needs sorting.
#include "common.glsl"
in vec3 vWorld;
in vec3 vNormal;
in float vShore;
layout(location = 0) out vec4 outColor;
void main() {
    vec3 n = normalize(vNormal);
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
