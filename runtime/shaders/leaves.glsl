// The leaf cards' cut (leaves.hpp), for surface.frag and depth.frag built with TREE: dithered
// alpha. The cutoff varies by ±0.15 about 0.5 over a 4 × 4 ordered (Bayer) pattern of the pixel,
// so the anti-aliased rim of each leaf dissolves over a few pixels instead of stepping, while the
// coverage-preserving mips keep far crowns as dense as near ones. The depth pre-pass and the colour
// pass see the same pixels, so they cut the same fragments; the shadow map dithers on its own texels.
layout(binding = 16) uniform sampler2D leaves;

bool leafCut(float alpha) {
    const float bayer[16] = float[16](0.0, 8.0, 2.0, 10.0, 12.0, 4.0, 14.0, 6.0, 3.0, 11.0, 1.0, 9.0, 15.0, 7.0, 13.0, 5.0);
    ivec2 p = ivec2(gl_FragCoord.xy) & 3;
    float threshold = 0.5 + 0.3 * ((bayer[p.y * 4 + p.x] + 0.5) / 16.0 - 0.5);
    return alpha < threshold;
}
