// Irradiance from the probes (issue 14; probes.hpp): the injected volume maps each lattice
// cell around the player to a tile of the cache texture (0: no probe there), and a surface
// blends its 8 surrounding probes. A tile is 5 × 5 texels: the ambient cube as an octahedral
// irradiance map (low, mid) or the 9 SH L2 radiance coefficients (high). Every texel's alpha
// is the probe's tag: 1 outdoors (OUT), 2 under a roof (IN) from the overlook depth; with
// anti-leak on, a surface blends only probes of its own tag.
#include "probes.glsl"
layout(std140, binding = 3) uniform Probes {
    vec4 origin;  // xyz: the probe of cell (0, 0, 0); w: spacing (m)
    ivec4 dims;   // xyz: the volume in cells; w: 0 off, 1 ambient cube, 2 SH L2
    vec4 cache;   // x: tiles per row; y: 1 / cache texels; z: anti-leak (1 on); w: 0
} probes;
layout(binding = 11) uniform sampler2D probeCache;
layout(binding = 12) uniform isampler3D probeIndex;
layout(binding = 15) uniform sampler2D probeMoments;  // per probe 6 texels (faces): mean, mean² distance
layout(binding = 6) uniform sampler2D overlookDepthTexture;

// The height of the highest surface over xz (terrain or roof) from the overlook depth;
// -1e9 outside the overlook's area.
float overlookHeight(vec2 xz) {
    vec2 uv = (xz - frame.overlook.xy) / frame.overlook.zw;
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) return -1e9;
    float depth = textureLod(overlookDepthTexture, uv, 0.0).r;
    return frame.overlookDepth.x - (frame.overlookDepth.y + depth * frame.overlookDepth.z);
}

// IN: something (a roof) stands more than 0.25 m above p.
bool underRoof(vec3 p) { return overlookHeight(p.xz) > p.y + 0.25; }

// Irradiance of the probe in cache tile `slot` at normal n; w: its tag (1 OUT, 2 IN).
vec4 probeTileIrradiance(int slot, vec3 n) {
    int perRow = int(probes.cache.x);
    ivec2 tile = ivec2(slot % perRow, slot / perRow) * 5;
    if (probes.dims.w == 2) {
        vec3 c[9];
        vec4 first = texelFetch(probeCache, tile, 0);
        c[0] = first.rgb;
        for (int i = 1; i < 9; ++i) c[i] = texelFetch(probeCache, tile + ivec2(i % 5, i / 5), 0).rgb;
        return vec4(max(shIrradiance(c, n), vec3(0.0)), first.a);
    }
    // Every texel of a tile holds the tag in alpha: the bilinear sample keeps it.
    vec2 t = clamp((octEncode(n) * 0.5 + 0.5) * 5.0, vec2(0.5), vec2(4.5));
    return textureLod(probeCache, (vec2(tile) + t) * probes.cache.y, 0.0);
}

// How likely the probe of cache `slot` at `probe` sees p (DDGI's Chebyshev test on the depth
// moments of the cube face that looks towards p), cubed as DDGI does to sharpen it.
float probeVisibility(int slot, vec3 probe, vec3 p) {
    vec3 d = p - probe, a = abs(d);
    int face = a.x >= a.y && a.x >= a.z ? (d.x >= 0.0 ? 0 : 1) : a.y >= a.z ? (d.y >= 0.0 ? 2 : 3) : (d.z >= 0.0 ? 4 : 5);
    int perRow = int(probes.cache.x);
    vec2 m = texelFetch(probeMoments, ivec2((slot % perRow) * 6 + face, slot / perRow), 0).rg;
    float v = chebyshevVisibility(length(d), m.x, m.y);
    return v * v * v;
}

// The probes' irradiance at p (normal n), blended trilinearly over the 8 surrounding probes;
// w: how much of p's cell the probes cover (0: no probe around p).
vec4 probeIrradiance(vec3 p, vec3 n) {
    if (probes.dims.w == 0) return vec4(0.0);
    vec3 g = (p - probes.origin.xyz) / probes.origin.w;
    ivec3 base = ivec3(floor(g));
    // Most of a frame lies beyond the lighting area: no probe, nothing to fetch.
    if (any(lessThan(base, ivec3(-1))) || any(greaterThanEqual(base, probes.dims.xyz))) return vec4(0.0);
    vec3 f = g - vec3(base);
    bool antiLeak = probes.cache.z > 0.5;
    float inside = antiLeak && underRoof(p + n * 0.3) ? 2.0 : 1.0;
    vec3 sum = vec3(0.0);
    float weights = 0.0, coverage = 0.0;
    for (int i = 0; i < 8; ++i) {
        ivec3 o = ivec3(i & 1, (i >> 1) & 1, i >> 2);
        ivec3 c = base + o;
        if (any(lessThan(c, ivec3(0))) || any(greaterThanEqual(c, probes.dims.xyz))) continue;
        int entry = texelFetch(probeIndex, c, 0).r;
        if (entry == 0) continue;
        vec4 e = probeTileIrradiance(entry - 1, n);
        if (antiLeak && abs(e.a - inside) > 0.5) continue;
        vec3 t = mix(1.0 - f, f, vec3(o));
        // A probe behind the surface counts less (it may see the other side of a thin wall).
        vec3 probe = probes.origin.xyz + vec3(c) * probes.origin.w;
        float facing = 0.5 * (1.0 + dot(normalize(probe - p + n * 1e-3), n));
        float w = t.x * t.y * t.z;
        coverage += w;
        w *= facing * facing + 0.05;
        // With anti-leak, a probe that cannot see p counts (almost) nothing.
        if (antiLeak) w *= max(probeVisibility(entry - 1, probe, p + n * 0.1), 1e-3);
        sum += w * e.rgb;
        weights += w;
    }
    return vec4(weights > 0.0 ? sum / weights : vec3(0.0), coverage);
}

// The second bounce's light at a captured surface: the nearest probe of the same tag, / π
// (one probe, not eight: the capture pays it per texel); w: 1 where there is one.
vec4 nearestProbeLight(vec3 p, vec3 n) {
    if (probes.dims.w == 0) return vec4(0.0);
    ivec3 c = ivec3(floor((p + n * 0.5 * probes.origin.w - probes.origin.xyz) / probes.origin.w + 0.5));
    if (any(lessThan(c, ivec3(0))) || any(greaterThanEqual(c, probes.dims.xyz))) return vec4(0.0);
    int entry = texelFetch(probeIndex, c, 0).r;
    if (entry == 0) return vec4(0.0);
    vec4 e = probeTileIrradiance(entry - 1, n);
    bool antiLeak = probes.cache.z > 0.5;
    if (antiLeak && abs(e.a - (underRoof(p + n * 0.3) ? 2.0 : 1.0)) > 0.5) return vec4(0.0);
    return vec4(e.rgb / kPi, 1.0);
}
