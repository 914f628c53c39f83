#version 450 core
// Probe capture G-buffer: albedo (alpha 1: something was hit; the clear leaves 0: sky), and
// the normal with the distance from the probe.
in vec3 vWorld;
flat in vec3 vNormal;
flat in vec3 vAlbedo;
layout(location = 2) uniform vec3 probe;
layout(location = 0) out vec4 outAlbedo;
layout(location = 1) out vec4 outNormalDistance;

void main() {
    outAlbedo = vec4(vAlbedo, 1.0);
    outNormalDistance = vec4(vNormal, length(vWorld - probe));
}
