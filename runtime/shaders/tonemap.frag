#version 450 core
// HDR → display: the frame's exposure (exposure.comp), the ACES filmic fit (Narkowicz 2015), sRGB encoding.
layout(binding = 0) uniform sampler2D hdr;
layout(std430, binding = 9) readonly buffer Exposure { float exposure; float sceneLuminance; float target; float pad; };
in vec2 vNdc;
layout(location = 0) out vec4 outColor;
vec3 aces(vec3 x) {
    return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}
vec3 toSrgb(vec3 c) {
    return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(0.0031308, c));
}
void main() {
    vec3 c = texelFetch(hdr, ivec2(gl_FragCoord.xy), 0).rgb;
    outColor = vec4(toSrgb(aces(c * exposure)), 1.0);
}
