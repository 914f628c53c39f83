// Building atlas sampling, GLSL 4.50 functions only; mirrors runtime/src/atlas.cpp
// (encodeBlock/blockInterior/atlasUv/atlasLod). Technique: "Tiling based on Atlas and Dynamic UV".
// The atlas texture must have mip levels 0..4 only (GL_TEXTURE_MAX_LEVEL = 4), min filter
// GL_LINEAR_MIPMAP_LINEAR, no hardware anisotropic filtering: the 16-texel padding around every
// block covers exactly an isotropic trilinear footprint up to level 4. Anisotropy is done here,
// tap by tap, each tap wrapped into the block; beyond level 4 the sample fades to the block's
// mean colour (AtlasMeans), so far ground neither bleeds nor shimmers.

// The material ID packed in COLOR_0 as binary RGBA: id = R + 2G + 4B + 8A.
uint atlasMaterialId(vec4 color0) {
    return uint(dot(round(clamp(color0, 0.0, 1.0)), vec4(1.0, 2.0, 4.0, 8.0)));
}

// The usable interior of a block, in atlas UV: xy origin, zw size. `code`: bits 0-3 slot
// (cell column slot % 4, row slot / 4 from the first image row), bit 4 half-size block,
// bits 5-6 quadrant (0 top-left, 1 top-right, 2 bottom-left, 3 bottom-right in image rows).
vec4 atlasBlockRect(uint code) {
    const float cell = 512.0 / 2048.0;
    const float padding = 16.0 / 2048.0;
    uint slot = code & 15u;
    bool isHalf = ((code >> 4u) & 1u) != 0u;
    uint quadrant = (code >> 5u) & 3u;
    vec2 origin = vec2(float(slot & 3u), float(slot >> 2u)) * cell;
    float blockSize = cell;
    if (isHalf) {
        blockSize = 0.5 * cell;
        origin += vec2(float(quadrant & 1u), float(quadrant >> 1u)) * blockSize;
    }
    return vec4(origin + padding, vec2(blockSize - 2.0 * padding));
}

// Samples the tile of block `rect` at metre UVs: wraps with fract inside the interior and takes
// the gradients from the UNWRAPPED coordinate, so the wrap seam keeps the right mip level.
// Call in uniform control flow (dFdx/dFdy). Fragment stage only: a vertex shader that includes
// this file for atlasBlockRect must #define DAWNFORGE_VERTEX_STAGE first.
#ifndef DAWNFORGE_VERTEX_STAGE
layout(std140, binding = 4) uniform AtlasMeans { vec4 atlasMean[128]; };  // linear, by block code

const float ATLAS_SIZE = 2048.0;
const float ATLAS_LAST_LEVEL = 4.0;
const int ATLAS_MAX_TAPS = 8;  // the widest anisotropy filtered: 8:1

// The block code (atlasBlockRect's argument) of an interior rectangle.
uint atlasBlockCode(vec4 rect) {
    vec2 cell = floor(rect.xy * 4.0);
    uint code = uint(cell.x) + 4u * uint(cell.y);
    if (rect.z < 0.2) {  // half-size: 224 / 2048 against 480 / 2048
        uvec2 q = uvec2(floor((rect.xy - cell * 0.25) * 8.0));
        code |= 16u | ((q.x + 2u * q.y) << 5u);
    }
    return code;
}

// Up to ATLAS_MAX_TAPS isotropic trilinear taps along the footprint's long axis, each at its own
// wrapped position, with gradients of the tap's own (short-axis) size.
vec4 sampleAtlas(sampler2D atlas, vec4 rect, vec2 uvMetres, float tileMetres) {
    vec2 tiles = uvMetres / tileMetres;
    vec2 gx = dFdx(tiles) * rect.zw, gy = dFdy(tiles) * rect.zw;  // atlas UV per pixel, unwrapped
    float lx = length(gx), ly = length(gy);
    float major = max(lx, ly), minor = min(lx, ly);
    int taps = int(clamp(ceil(major / max(minor, 1e-12)), 1.0, float(ATLAS_MAX_TAPS)));
    float footprint = max(minor, major / float(taps));
    vec2 step = (lx >= ly ? gx : gy) / rect.zw / float(taps);  // in tiles
    vec2 g = vec2(footprint, 0.0);
    vec4 sum = vec4(0.0);
    for (int i = 0; i < taps; ++i) {
        vec2 t = tiles + step * (float(i) + 0.5 - 0.5 * float(taps));
        sum += textureGrad(atlas, rect.xy + fract(t) * rect.zw, g, g.yx);
    }
    float lod = log2(max(footprint * ATLAS_SIZE, 1e-6));
    return mix(sum / float(taps), atlasMean[atlasBlockCode(rect)], smoothstep(ATLAS_LAST_LEVEL, ATLAS_LAST_LEVEL + 1.0, lod));
}
#endif
