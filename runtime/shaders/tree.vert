#version 450 core
// Trees: one species per draw, one instance per tree. Each vertex is bent by the wind
// (wind.glsl) in the tree's own space, then placed by the instance's transform.
#define DAWNFORGE_VERTEX_STAGE
#include "common.glsl"
#include "materials.glsl"
#include "atlas.glsl"
#include "surface.glsl"
#include "wind.glsl"
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec2 aUv0;
layout(location = 3) in vec2 aUv1;        // the element's Pivot Painter texel
layout(location = 5) in uint aMaterial;
layout(location = 6) in uvec4 aBlocks;    // per instance: 16 block codes, one byte each
layout(location = 7) in uint aBuilding;   // per instance: 0xffff (no building)
layout(location = 10) in mat4 aModel;     // per instance: tree space → world (turn and uniform scale)
#ifdef DEPTH_PASS
layout(location = 0) uniform mat4 depthViewProj;
out vec2 vLeafUv;   // depth.frag cuts the leaf cards out as surface.frag does
flat out uint vLeaf;
#endif
layout(location = 5) uniform vec4 wind;   // xyz: unit, level, where it blows to (world); w: speed (m/s)
layout(location = 6) uniform float windTime;
layout(location = 8) uniform vec3 modelOffset;  // the trees' frame in render space (camera-relative)
// The depth pre-pass and the colour pass compute the same position to the bit.
invariant gl_Position;
void main() {
    vec3 p = aPosition, n = aNormal;
    vec3 windDir = normalize(transpose(mat3(aModel)) * wind.xyz);
    windBend(p, n, aUv1, windDir, wind.w, windTime, dot(aModel[3].xz, vec2(0.37, 0.21)));
    vec3 world = (aModel * vec4(p, 1.0)).xyz + modelOffset;
#ifdef DEPTH_PASS
    vLeafUv = aUv0;
    vLeaf = (aMaterial & 15u) == kGround ? 1u : 0u;  // a leaf card
    gl_Position = depthViewProj * vec4(world, 1.0);
#else
    vWorld = world;
    vNormal = normalize(mat3(aModel) * n);
    vUv0 = aUv0;
    vUv1 = vec2(0.0);
    vUv2 = vec2(0.0);
    vLight = vec3(0.0, 0.0, -1.0);
    vMaterial = aMaterial & 15u;
    vRect = atlasBlockRect(blockCode(aBlocks, vMaterial));
    vTile = materials.tileMetres[vMaterial].x;
    vBuilding = aBuilding;
    gl_Position = frame.viewProj * vec4(world, 1.0);
#endif
}
