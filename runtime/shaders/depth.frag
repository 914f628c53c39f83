#version 450 core
// Depth-only passes (shadow map, overlook depth).
void main() {}
