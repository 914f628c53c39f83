// Ocean waves for a vertex shader: the maths of runtime/src/ocean.cpp (dawnforge::runtime
// gerstner(), noiseHeight(), oceanGridVertex()) in single precision. Functions only: no
// #version, no uniforms; the caller passes everything (packed as OceanWavesGpu in
// ocean.hpp):
//   dirs01 = (D0.x, D0.z, D1.x, D1.z), dirs23 = (D2.x, D2.z, D3.x, D3.z)  unit wave directions in xz
//   amplitude, wavelength, steepness, phase                              component i = wave i
//   noise: scale = texture repeats per metre, driftX / driftY = uv per second, component c = channel c
// A change here must be made in ocean.cpp too.

const float OCEAN_PI = 3.14159265358979;
const float OCEAN_GRAVITY = 9.81;                           // kOceanGravity
const vec4 OCEAN_NOISE_WEIGHTS = vec4(0.4, 0.3, 0.2, 0.1);  // kNoiseWeights

// The Gerstner part at the plane point x0 = (x, z), time t: returns the offset D so that the
// surface point is (x0.x, 0, x0.y) + D. normal: unit, upward. jacobian: det of the horizontal
// map's derivative, ≤ 0 where the surface folds (foam).
vec3 gerstnerWaves(vec2 x0, float t, float attenuation, vec4 dirs01, vec4 dirs23, vec4 amplitude,
                   vec4 wavelength, vec4 steepness, vec4 phase, out vec3 normal, out float jacobian) {
    vec2 dir[4] = vec2[4](dirs01.xy, dirs01.zw, dirs23.xy, dirs23.zw);
    vec3 displacement = vec3(0.0);
    vec3 dPdx = vec3(1.0, 0.0, 0.0);
    vec3 dPdz = vec3(0.0, 0.0, 1.0);
    for (int i = 0; i < 4; ++i) {
        float a = amplitude[i] * attenuation;
        float k = 2.0 * OCEAN_PI / wavelength[i];
        float omega = sqrt(OCEAN_GRAVITY * k);
        float theta = k * dot(dir[i], x0) - omega * t + phase[i];
        float s = sin(theta);
        float c = cos(theta);
        vec2 d = dir[i];
        float qa = steepness[i] * a;
        displacement += vec3(qa * d.x * c, a * s, qa * d.y * c);
        float qaks = qa * k * s;
        float akc = a * k * c;
        dPdx += vec3(-qaks * d.x * d.x, akc * d.x, -qaks * d.x * d.y);
        dPdz += vec3(-qaks * d.y * d.x, akc * d.y, -qaks * d.y * d.y);
    }
    normal = normalize(cross(dPdz, dPdx));
    jacobian = dPdx.x * dPdz.z - dPdz.x * dPdx.z;
    return displacement;
}

vec3 gerstnerDisplacement(vec2 x0, float t, float attenuation, vec4 dirs01, vec4 dirs23, vec4 amplitude,
                          vec4 wavelength, vec4 steepness, vec4 phase, out vec3 normal) {
    float jacobian;
    return gerstnerWaves(x0, t, attenuation, dirs01, dirs23, amplitude, wavelength, steepness, phase, normal,
                         jacobian);
}

// Detail height from the 4-channel noise texture (GL_LINEAR, GL_REPEAT): channel c sampled at
// x0 * scale[c] + (driftX[c], driftY[c]) * t, weighted by OCEAN_NOISE_WEIGHTS around 0.5.
float noiseHeight(sampler2D noise, vec2 x0, float t, float amplitude, vec4 scale, vec4 driftX, vec4 driftY,
                  float attenuation) {
    float sum = 0.0;
    for (int c = 0; c < 4; ++c) {
        vec2 uv = x0 * scale[c] + vec2(driftX[c], driftY[c]) * t;
        sum += OCEAN_NOISE_WEIGHTS[c] * (textureLod(noise, uv, 0.0)[c] - 0.5);
    }
    return amplitude * attenuation * sum;
}

// The undisplaced projected-grid vertex: the ray through ndc (points at NDC z = -1 and 1)
// intersected with the plane y = level.
vec3 oceanGridVertex(vec2 ndc, mat4 inverseViewProjection, float level) {
    vec4 a = inverseViewProjection * vec4(ndc, -1.0, 1.0);
    vec4 b = inverseViewProjection * vec4(ndc, 1.0, 1.0);
    vec3 p0 = a.xyz / a.w;
    vec3 p1 = b.xyz / b.w;
    vec3 d = p1 - p0;
    float s = (level - p0.y) / d.y;
    return p0 + s * d;
}
