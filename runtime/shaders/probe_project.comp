#version 450 core
// Probe capture, step 3: light the G-buffer of each probe of the batch and project it. One
// work group per probe: every texel's radiance (the sky where nothing was hit; else the
// face's albedo × (sun with the shadow map + ambient + street lamps), the ambient from the
// nearest probe already captured where there is one: the second bounce) is projected into SH
// L2, weighted by the texel's solid angle, and reduced in shared memory; so are the mean and
// mean square of the distances each cube face saw (the depth moments of the Chebyshev
// visibility test). The probe's cache tile gets the 9 coefficients (SH) or the 5 × 5
// octahedral irradiance map (ambient cube), with its IN/OUT tag.
#include "common.glsl"
#include "probe_box.glsl"
layout(local_size_x = 128) in;
layout(binding = 13) uniform sampler2D gAlbedo;
layout(binding = 14) uniform sampler2D gNormalDistance;
layout(rgba16f, binding = 0) uniform writeonly image2D cacheImage;
layout(rg32f, binding = 1) uniform writeonly image2D momentImage;  // per probe 6 texels: mean, mean² distance per face
layout(std430, binding = 3) readonly buffer Batch { vec4 batch[]; };  // xyz: position; w: cache slot
layout(std430, binding = 4) writeonly buffer Coefficients { vec4 coefficients[]; };  // 9 per slot; w: tag
layout(std430, binding = 5) readonly buffer SolidAngles { float solidAngle[]; };  // per texel of a face
layout(location = 0) uniform int faceSize;
layout(location = 1) uniform int multiBounce;
layout(location = 2) uniform float skyDistance;  // what a sky texel counts as in the depth moments
// Street lamps near the batch (city.json's "lamps"): position, then linear colour; the bake's
// lamp model (bake/lighting.hpp lampIrradiance): intensity, softening radius, range.
layout(std430, binding = 8) readonly buffer Lamps { vec4 lamps[]; };
layout(location = 3) uniform int lampCount;
layout(location = 4) uniform vec3 lampModel;

// The bake's lamp irradiance: I · s(dir.y) · n·dir · (1 − (d/range)⁴)² / (d² + r²), where s
// fades in as the lamp rises above the point; no shadow (a lamp behind a wall lights it too).
vec3 streetLampLight(vec3 p, vec3 n) {
    vec3 sum = vec3(0.0);
    for (int i = 0; i < lampCount; ++i) {
        vec3 d = lamps[2 * i].xyz - p;
        float d2 = dot(d, d), dist = sqrt(d2);
        if (dist >= lampModel.z || dist <= 0.0) continue;
        vec3 dir = d / dist;
        float cosine = dot(n, dir);
        if (cosine <= 0.0) continue;
        float t = clamp((dir.y + 0.2) / 0.4, 0.0, 1.0), q = dist / lampModel.z, q4 = q * q * q * q;
        sum += lamps[2 * i + 1].rgb * (lampModel.x * t * t * (3.0 - 2.0 * t) * cosine * (1.0 - q4) * (1.0 - q4) /
                                       (d2 + lampModel.y * lampModel.y));
    }
    return sum;
}
shared vec3 partial[9][128];

vec3 texelRadiance(vec3 probe, vec3 dir, vec4 albedo, vec4 normalDistance) {
    if (albedo.a < 0.5) return skyColor(dir);
    vec3 hit = probe + dir * normalDistance.w, n = normalDistance.xyz;
    float ndl = max(dot(n, frame.sunDir.xyz), 0.0);
    float shadow = ndl > 0.0 ? sunShadowCoarse(hit, n) : 0.0;
    // Sky AO, coarsely: a surface under a roof (IN) sees no sky of its own, only what the
    // probes already captured bring it; nor does a street lamp light it.
    bool indoors = underRoof(hit + n * 0.3);
    vec3 hemi = indoors ? vec3(0.0) : hemisphereLight(n);
    vec4 bounce = multiBounce != 0 ? nearestProbeLight(hit, n) : vec4(0.0);
    vec3 ambient = bounce.w > 0.0 ? bounce.rgb : hemi;
    vec3 lamp = indoors || frame.sunDir.w <= 0.0 ? vec3(0.0) : streetLampLight(hit, n) * frame.sunDir.w;
    return albedo.rgb * (frame.sunColor.rgb * ndl * shadow + ambient + lamp);
}

// Sums the work group's values[0 .. count) into partial[i][0] (a tree over the 128 lanes).
void reduce(vec3 values[9], int count) {
    uint lane = gl_LocalInvocationID.x;
    for (int i = 0; i < count; ++i) partial[i][lane] = values[i];
    barrier();
    for (uint stride = 64u; stride > 0u; stride >>= 1u) {
        if (lane < stride)
            for (int i = 0; i < count; ++i) partial[i][lane] += partial[i][lane + stride];
        barrier();
    }
}

void main() {
    uint probe = gl_WorkGroupID.x, lane = gl_LocalInvocationID.x;
    vec3 p = batch[probe].xyz;
    int slot = int(batch[probe].w), faceTexels = faceSize * faceSize;
    vec3 acc[9], moments[9];  // moments: 6 faces used
    for (int i = 0; i < 9; ++i) acc[i] = moments[i] = vec3(0.0);
    for (int t = int(lane); t < 6 * faceTexels; t += 128) {
        int f = t / faceTexels, x = t % faceSize, y = (t % faceTexels) / faceSize;
        ivec2 g = ivec2(f * faceSize + x, int(probe) * faceSize + y);
        vec2 s = (vec2(x, y) + 0.5) / float(faceSize) * 2.0 - 1.0;
        vec3 dir = normalize(kFaceForward[f] + s.x * cross(kFaceForward[f], kFaceUp[f]) + s.y * kFaceUp[f]);
        vec4 albedo = texelFetch(gAlbedo, g, 0), normalDistance = texelFetch(gNormalDistance, g, 0);
        vec3 radiance = texelRadiance(p, dir, albedo, normalDistance);
        float y9[9];
        shBasis(dir, y9);
        float dOmega = solidAngle[y * faceSize + x];
        for (int i = 0; i < 9; ++i) acc[i] += radiance * (y9[i] * dOmega);
        float distance = albedo.a < 0.5 ? skyDistance : normalDistance.w;
        moments[f] += vec3(distance, distance * distance, 1.0) * dOmega;
    }
    vec3 c[9];
    reduce(acc, 9);
    for (int i = 0; i < 9; ++i) c[i] = partial[i][0];
    barrier();  // every lane has read the SH before the moments reuse the shared memory
    reduce(moments, 6);
    int perRow = int(probes.cache.x);
    if (lane < 6u) {
        vec3 m = partial[lane][0];
        imageStore(momentImage, ivec2((slot % perRow) * 6 + int(lane), slot / perRow), vec4(m.x / m.z, m.y / m.z, 0.0, 0.0));
    }
    if (lane >= 25u) return;
    float tag = underRoof(p) ? 2.0 : 1.0;
    if (lane < 9u) coefficients[slot * 9 + int(lane)] = vec4(c[lane], tag);
    ivec2 texel = ivec2(slot % perRow, slot / perRow) * 5 + ivec2(int(lane) % 5, int(lane) / 5);
    vec3 value;
    if (probes.dims.w == 2) {
        value = lane < 9u ? c[lane] : vec3(0.0);
    } else {
        vec2 e = (vec2(int(lane) % 5, int(lane) / 5) + 0.5) / 5.0 * 2.0 - 1.0;
        value = max(shIrradiance(c, octDecode(e)), vec3(0.0));
    }
    imageStore(cacheImage, texel, vec4(value, tag));
}
