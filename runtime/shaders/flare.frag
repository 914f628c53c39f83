#version 450 core
// Lens flare elements (runtime/src/flares.hpp): drawn additively into the HDR colour.
in vec2 vUv;
in vec3 vColour;
flat in int vShape;
layout(location = 0) out vec4 outColor;

const int kGlow = 0, kGhost = 1, kHexGhost = 2, kHalo = 3;

// Distance to the centre measured in a regular hexagon (the aperture's shape): 1 on its edge.
float hexRadius(vec2 p) {
    p = abs(p);
    return max(p.x * 0.866025 + p.y * 0.5, p.y) / 0.866025;
}

float shape(vec2 uv) {
    float r = length(uv);
    if (vShape == kGlow) {
        // A bright core, a soft falloff and six faint diffraction spikes.
        float spikes = pow(abs(cos(3.0 * atan(uv.y, uv.x))), 60.0) * pow(max(1.0 - r, 0.0), 2.0);
        return exp(-r * r * 60.0) * 1.5 + pow(max(1.0 - r, 0.0), 4.0) + 0.35 * spikes;
    }
    if (vShape == kHalo) return exp(-pow((r - 0.82) / 0.07, 2.0)) * smoothstep(1.0, 0.95, r);
    // Ghosts: an out-of-focus image of the aperture, slightly brighter at the rim.
    float d = vShape == kHexGhost ? hexRadius(uv) : r;
    return smoothstep(1.0, 0.9, d) * (0.55 + 0.45 * smoothstep(0.4, 0.95, d));
}

void main() {
    outColor = vec4(vColour * shape(vUv), 0.0);
}
