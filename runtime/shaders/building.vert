#version 450 core
// Static meshes (buildings, ground). The block mapping (material → atlas block) is
// per-instance data, so one mesh can wear different block combinations in one draw.
#define DAWNFORGE_VERTEX_STAGE
#include "common.glsl"
#include "atlas.glsl"
#include "surface.glsl"
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec2 aUv0;
layout(location = 3) in vec2 aUv1;
layout(location = 4) in vec2 aUv2;
layout(location = 5) in uint aMaterial;
layout(location = 6) in uvec4 aBlocks;    // per instance: 16 block codes, one byte each
layout(location = 7) in uint aBuilding;   // per instance: the building id (room styles, lit windows)
layout(location = 9) in vec3 aLight;      // baked lightmap (u, v, layer); layer -1: none; -2: baked in uv1, uv2
layout(location = 8) uniform vec3 modelOffset;  // the mesh's frame in render space (camera-relative)
#ifdef DEPTH_PASS
layout(location = 0) uniform mat4 depthViewProj;
#endif
// The depth pre-pass and the colour pass compute the same position to the bit.
invariant gl_Position;
void main() {
    vec3 world = aPosition + modelOffset;
#ifdef DEPTH_PASS
    gl_Position = depthViewProj * vec4(world, 1.0);
#else
    vWorld = world;
    vNormal = aNormal;
    vUv0 = aUv0;
    vUv1 = aUv1;
    vUv2 = aUv2;
    vLight = aLight;
    vMaterial = aMaterial & 15u;
    vRect = atlasBlockRect(blockCode(aBlocks, vMaterial));
    vTile = materials.tileMetres[vMaterial].x;
    vBuilding = aBuilding;
    gl_Position = frame.viewProj * vec4(world, 1.0);
#endif
}
