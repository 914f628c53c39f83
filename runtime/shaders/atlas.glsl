// Building atlas sampling, GLSL 4.50 functions only; mirrors runtime/src/atlas.cpp
// (encodeBlock/blockInterior/atlasUv/atlasLod). Technique: "Tiling based on Atlas and Dynamic UV".
// The atlas texture must have mip levels 0..4 only (GL_TEXTURE_MAX_LEVEL = 4), min filter
// GL_LINEAR_MIPMAP_LINEAR, no anisotropic filtering: the 16-texel padding around every block
// covers exactly that footprint.

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
vec4 sampleAtlas(sampler2D atlas, vec4 rect, vec2 uvMetres, float tileMetres) {
    vec2 tiles = uvMetres / tileMetres;
    vec2 unwrapped = tiles * rect.zw;
    vec2 uv = rect.xy + fract(tiles) * rect.zw;
    return textureGrad(atlas, uv, dFdx(unwrapped), dFdy(unwrapped));
}
#endif
