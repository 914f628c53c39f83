// Probe arithmetic in GLSL, the same as probe_math.hpp on the CPU (the tests hold the two
// together through gpu_checks.comp): SH L2 basis and Lambertian irradiance, the octahedral
// map (+Y at its centre), ambient-cube weights and Chebyshev visibility.

// The nine real SH basis functions at unit direction d.
void shBasis(vec3 d, out float y[9]) {
    y[0] = 0.282094791773878;
    y[1] = 0.488602511902920 * d.y;
    y[2] = 0.488602511902920 * d.z;
    y[3] = 0.488602511902920 * d.x;
    y[4] = 1.092548430592079 * d.x * d.y;
    y[5] = 1.092548430592079 * d.y * d.z;
    y[6] = 0.315391565252520 * (3.0 * d.z * d.z - 1.0);
    y[7] = 1.092548430592079 * d.x * d.z;
    y[8] = 0.546274215296040 * (d.x * d.x - d.y * d.y);
}

// Irradiance at unit normal n under radiance coefficients c (one rgb per coefficient).
vec3 shIrradiance(vec3 c[9], vec3 n) {
    const float band[9] = float[9](3.14159265, 2.09439510, 2.09439510, 2.09439510, 0.78539816, 0.78539816,
                                   0.78539816, 0.78539816, 0.78539816);
    float y[9];
    shBasis(n, y);
    vec3 e = vec3(0.0);
    for (int i = 0; i < 9; ++i) e += band[i] * y[i] * c[i];
    return e;
}

vec2 signNotZero(vec2 v) { return vec2(v.x >= 0.0 ? 1.0 : -1.0, v.y >= 0.0 ? 1.0 : -1.0); }

vec2 octEncode(vec3 d) {
    vec2 p = d.xz / (abs(d.x) + abs(d.y) + abs(d.z));
    return d.y < 0.0 ? (1.0 - abs(p.yx)) * signNotZero(p) : p;
}

vec3 octDecode(vec2 e) {
    vec3 v = vec3(e.x, 1.0 - abs(e.x) - abs(e.y), e.y);
    if (v.y < 0.0) v.xz = (1.0 - abs(v.zx)) * signNotZero(v.xz);
    return normalize(v);
}

// Irradiance from an ambient cube (+X, -X, +Y, -Y, +Z, -Z): the faces n leans towards,
// weighted by n_i² (they sum to 1).
vec3 ambientIrradiance(vec3 cube[6], vec3 n) {
    vec3 w = n * n;
    return w.x * (n.x >= 0.0 ? cube[0] : cube[1]) + w.y * (n.y >= 0.0 ? cube[2] : cube[3]) +
           w.z * (n.z >= 0.0 ? cube[4] : cube[5]);
}

float chebyshevVisibility(float distance, float mean, float meanSquare) {
    if (distance <= mean) return 1.0;
    float variance = max(meanSquare - mean * mean, 1e-12);
    float d = distance - mean;
    return variance / (variance + d * d);
}
