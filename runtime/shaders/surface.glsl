// What building.vert and vat.vert hand to surface.frag.
#ifdef DAWNFORGE_VERTEX_STAGE
#define VARYING out
#else
#define VARYING in
#endif
VARYING vec3 vWorld;
VARYING vec3 vNormal;
VARYING vec2 vUv0;
VARYING vec2 vUv1;
VARYING vec2 vUv2;
VARYING vec3 vLight;     // baked lightmap (u, v, layer); layer -1: not baked; -2: baked in vUv1, vUv2
flat VARYING uint vMaterial;
flat VARYING vec4 vRect;     // atlas block interior (origin, size) for this material
flat VARYING float vTile;    // metres per tile repeat
flat VARYING uint vBuilding; // instance id (room styles, lit windows)
#undef VARYING

layout(std140, binding = 1) uniform Materials {
    vec4 tileMetres[16];  // x: metres one tile repeat covers
} materials;

// The block code of `material` among the 16 packed bytes of an instance's mapping.
uint blockCode(uvec4 blocks, uint material) {
    return (blocks[material >> 2u] >> ((material & 3u) * 8u)) & 0xffu;
}
