#version 450 core
// Auto exposure (ARCHITECTURE.md 7, Exposure): the centre-weighted log-average luminance of the
// HDR frame, from 64 x 64 samples each the mean of a 2 x 2 pixel block, and the frame's exposure:
// key (lowered at night on the CPU) / average within [min, max], reached at once (blend 1) or a share of the way in stops.
// One work group; the sum runs in a fixed order, so a frame's exposure is deterministic.
layout(local_size_x = 256) in;
layout(binding = 0) uniform sampler2D hdr;
layout(std430, binding = 9) buffer Exposure { float exposure; float sceneLuminance; float target; float pad; };
layout(location = 0) uniform vec4 settings;  // key, min, max, fixed (> 0: pinned to it)
layout(location = 1) uniform float blend;    // the share of the way, in stops, from the last exposure to the target

const int kGrid = 64;
const int kPerThread = kGrid * kGrid / 256;
shared float sums[256];
shared float weights[256];

float luminance(ivec2 p, ivec2 last) {
    vec3 c = texelFetch(hdr, min(p, last), 0).rgb;
    return dot(max(c, vec3(0.0)), vec3(0.2126, 0.7152, 0.0722));
}

void main() {
    uint i = gl_LocalInvocationIndex;
    ivec2 size = textureSize(hdr, 0), last = size - 1;
    float s = 0.0, w = 0.0;
    for (int k = 0; k < kPerThread; ++k) {
        int n = int(i) + 256 * k;
        vec2 cell = (vec2(n % kGrid, n / kGrid) + 0.5) / float(kGrid);
        ivec2 p = ivec2(cell * vec2(size));
        float lum = 0.25 * (luminance(p, last) + luminance(p + ivec2(1, 0), last) + luminance(p + ivec2(0, 1), last) +
                            luminance(p + ivec2(1, 1), last));
        vec2 d = 2.0 * cell - 1.0;
        float weight = 1.0 - 0.5 * min(dot(d, d), 1.0);  // the middle counts twice the corners
        s += weight * log2(max(lum, 1e-4));
        w += weight;
    }
    sums[i] = s;
    weights[i] = w;
    for (uint half_ = 128u; half_ > 0u; half_ >>= 1u) {
        barrier();
        if (i < half_) {
            sums[i] += sums[i + half_];
            weights[i] += weights[i + half_];
        }
    }
    if (i != 0u) return;
    float average = exp2(sums[0] / weights[0]);
    float t = settings.w > 0.0 ? settings.w : clamp(settings.x / average, settings.y, settings.z);
    float from = exposure > 0.0 ? exposure : t;
    exposure = blend >= 1.0 ? t : exp2(mix(log2(from), log2(t), blend));
    sceneLuminance = average;
    target = t;
}
