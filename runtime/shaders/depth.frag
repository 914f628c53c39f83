#version 450 core
// Depth-only passes (shadow map, overlook depth). Trees (TREE): leaf cards are cut out as in the
// colour pass (leaves.glsl).
#ifdef TREE
#include "leaves.glsl"
in vec2 vLeafUv;
flat in uint vLeaf;
#endif
void main() {
#ifdef TREE
    if (vLeaf != 0u && leafCut(texture(leaves, vLeafUv).a)) discard;
#endif
}
