#version 450 core
// Depth-only passes (shadow map, overlook depth). Trees (TREE): leaf cards are cut out where the
// leaf picture's alpha is below the cutoff, as in the colour pass.
#ifdef TREE
layout(binding = 16) uniform sampler2D leaves;
in vec2 vLeafUv;
flat in uint vLeaf;
#endif
void main() {
#ifdef TREE
    if (vLeaf != 0u && texture(leaves, vLeafUv).a < 0.5) discard;
#endif
}
