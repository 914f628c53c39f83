#version 450 core
// Probe capture, step 3: light the G-buffer of each probe of the batch and project it. One
// work group per probe: every texel's radiance (the sky where nothing was hit; else the
// face's albedo × (sun with the shadow map + ambient), the ambient from the probes already
// captured where there are some: the second bounce, from the nearest one) is projected into SH L2, weighted by the
// texel's solid angle, and reduced in shared memory. The probe's cache tile gets the 9
// coefficients (SH) or the 5 × 5 octahedral irradiance map (ambient cube), with its IN/OUT tag.
#include "common.glsl"
#include "probe_box.glsl"
layout(local_size_x = 128) in;
layout(binding = 13) uniform sampler2D gAlbedo;
layout(binding = 14) uniform sampler2D gNormalDistance;
layout(rgba16f, binding = 0) uniform writeonly image2D cacheImage;
layout(std430, binding = 3) readonly buffer Batch { vec4 batch[]; };  // xyz: position; w: cache slot
layout(std430, binding = 4) writeonly buffer Coefficients { vec4 coefficients[]; };  // 9 per slot; w: tag
layout(std430, binding = 5) readonly buffer SolidAngles { float solidAngle[]; };  // per texel of a face
layout(location = 0) uniform int faceSize;
layout(location = 1) uniform int multiBounce;
shared vec3 partial[9][128];

vec3 texelRadiance(vec3 probe, vec3 dir, vec4 albedo, vec4 normalDistance) {
    if (albedo.a < 0.5) return skyColor(dir);
    vec3 hit = probe + dir * normalDistance.w, n = normalDistance.xyz;
    float ndl = max(dot(n, frame.sunDir.xyz), 0.0);
    float shadow = ndl > 0.0 ? sunShadow(hit, n) : 0.0;
    // Sky AO, coarsely: a surface under a roof (IN) sees no sky of its own, only what the
    // probes already captured bring it.
    vec3 hemi = underRoof(hit + n * 0.3) ? vec3(0.0)
              : mix(frame.groundColor.rgb, 0.5 * (frame.skyZenith.rgb + frame.skyHorizon.rgb), n.y * 0.5 + 0.5) * 0.9;
    vec4 bounce = multiBounce != 0 ? nearestProbeLight(hit, n) : vec4(0.0);
    vec3 ambient = bounce.w > 0.0 ? bounce.rgb : hemi;
    return albedo.rgb * (frame.sunColor.rgb * ndl * shadow + ambient);
}

void main() {
    uint probe = gl_WorkGroupID.x, lane = gl_LocalInvocationID.x;
    vec3 p = batch[probe].xyz;
    int slot = int(batch[probe].w), faceTexels = faceSize * faceSize;
    vec3 acc[9];
    for (int i = 0; i < 9; ++i) acc[i] = vec3(0.0);
    for (int t = int(lane); t < 6 * faceTexels; t += 128) {
        int f = t / faceTexels, x = t % faceSize, y = (t % faceTexels) / faceSize;
        ivec2 g = ivec2(f * faceSize + x, int(probe) * faceSize + y);
        vec2 s = (vec2(x, y) + 0.5) / float(faceSize) * 2.0 - 1.0;
        vec3 dir = normalize(kFaceForward[f] + s.x * cross(kFaceForward[f], kFaceUp[f]) + s.y * kFaceUp[f]);
        vec3 radiance = texelRadiance(p, dir, texelFetch(gAlbedo, g, 0), texelFetch(gNormalDistance, g, 0));
        float y9[9];
        shBasis(dir, y9);
        float dOmega = solidAngle[y * faceSize + x];
        for (int i = 0; i < 9; ++i) acc[i] += radiance * (y9[i] * dOmega);
    }
    for (int i = 0; i < 9; ++i) partial[i][lane] = acc[i];
    barrier();
    for (uint stride = 64u; stride > 0u; stride >>= 1u) {
        if (lane < stride)
            for (int i = 0; i < 9; ++i) partial[i][lane] += partial[i][lane + stride];
        barrier();
    }
    if (lane >= 25u) return;
    vec3 c[9];
    for (int i = 0; i < 9; ++i) c[i] = partial[i][0];
    float tag = underRoof(p) ? 2.0 : 1.0;
    if (lane < 9u) coefficients[slot * 9 + int(lane)] = vec4(c[lane], tag);
    int perRow = int(probes.cache.x);
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
