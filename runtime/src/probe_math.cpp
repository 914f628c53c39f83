// Probe arithmetic (probe_math.hpp): SH L2, cube-map projection, octahedral maps, ambient
// cubes and Chebyshev visibility.
#include <dawnforge/runtime/probe_math.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace dawnforge::runtime {

namespace {

constexpr double kPi = std::numbers::pi;

// The sign of v, with 0 counted as positive (the octahedral fold must not lose a quadrant).
double signNotZero(double v) { return v >= 0.0 ? 1.0 : -1.0; }

// The area of the part of a cube face (at distance 1) from its centre to (x, y), as a solid angle.
double cornerSolidAngle(double x, double y) { return std::atan2(x * y, std::sqrt(x * x + y * y + 1.0)); }

}  // namespace

ShRgb& ShRgb::operator+=(const ShRgb& o) {
    for (int i = 0; i < kShCoefficients; ++i) c[std::size_t(i)] += o.c[std::size_t(i)];
    return *this;
}

Sh9 shBasis(glm::dvec3 d) {
    const double x = d.x, y = d.y, z = d.z;
    return {0.282094791773878,
            0.488602511902920 * y,
            0.488602511902920 * z,
            0.488602511902920 * x,
            1.092548430592079 * x * y,
            1.092548430592079 * y * z,
            0.315391565252520 * (3.0 * z * z - 1.0),
            1.092548430592079 * x * z,
            0.546274215296040 * (x * x - y * y)};
}

double shLambert(int band) {
    static constexpr double kA[3] = {kPi, 2.0 * kPi / 3.0, kPi / 4.0};
    return kA[std::clamp(band, 0, 2)];
}

ShRgb shDirectional(glm::dvec3 d, glm::dvec3 radiance) {
    const Sh9 y = shBasis(glm::normalize(d));
    ShRgb out;
    for (int i = 0; i < kShCoefficients; ++i) out.c[std::size_t(i)] = y[std::size_t(i)] * radiance;
    return out;
}

glm::dvec3 shIrradiance(const ShRgb& radiance, glm::dvec3 n) {
    static constexpr int kBand[kShCoefficients] = {0, 1, 1, 1, 2, 2, 2, 2, 2};
    const Sh9 y = shBasis(n);
    glm::dvec3 e(0.0);
    for (int i = 0; i < kShCoefficients; ++i) e += shLambert(kBand[i]) * y[std::size_t(i)] * radiance.c[std::size_t(i)];
    return e;
}

glm::dvec3 cubeTexelDirection(int face, int x, int y, int size) {
    const double s = 2.0 * (x + 0.5) / size - 1.0, t = 2.0 * (y + 0.5) / size - 1.0;
    glm::dvec3 d;
    switch (face) {
        case 0: d = {1.0, -t, -s}; break;
        case 1: d = {-1.0, -t, s}; break;
        case 2: d = {s, 1.0, t}; break;
        case 3: d = {s, -1.0, -t}; break;
        case 4: d = {s, -t, 1.0}; break;
        default: d = {-s, -t, -1.0}; break;
    }
    return glm::normalize(d);
}

double cubeTexelSolidAngle(int x, int y, int size) {
    const double x0 = 2.0 * x / size - 1.0, x1 = 2.0 * (x + 1) / size - 1.0;
    const double y0 = 2.0 * y / size - 1.0, y1 = 2.0 * (y + 1) / size - 1.0;
    return cornerSolidAngle(x1, y1) - cornerSolidAngle(x0, y1) - cornerSolidAngle(x1, y0) + cornerSolidAngle(x0, y0);
}

ShRgb shProjectCube(const std::array<std::vector<glm::vec3>, 6>& faces, int size) {
    ShRgb out;
    for (int f = 0; f < 6; ++f)
        for (int y = 0; y < size; ++y)
            for (int x = 0; x < size; ++x) {
                const glm::dvec3 radiance(faces[std::size_t(f)][std::size_t(y * size + x)]);
                const Sh9 basis = shBasis(cubeTexelDirection(f, x, y, size));
                const double w = cubeTexelSolidAngle(x, y, size);
                for (int i = 0; i < kShCoefficients; ++i) out.c[std::size_t(i)] += (w * basis[std::size_t(i)]) * radiance;
            }
    return out;
}

// +Y is the centre of the map: the upper hemisphere fills the inner diamond.
glm::dvec2 octEncode(glm::dvec3 d) {
    const double l1 = std::abs(d.x) + std::abs(d.y) + std::abs(d.z);
    glm::dvec2 p(d.x / l1, d.z / l1);
    if (d.y < 0.0) p = glm::dvec2((1.0 - std::abs(p.y)) * signNotZero(p.x), (1.0 - std::abs(p.x)) * signNotZero(p.y));
    return p;
}

glm::dvec3 octDecode(glm::dvec2 e) {
    glm::dvec3 v(e.x, 1.0 - std::abs(e.x) - std::abs(e.y), e.y);
    if (v.y < 0.0) {
        const double x = (1.0 - std::abs(v.z)) * signNotZero(v.x), z = (1.0 - std::abs(v.x)) * signNotZero(v.z);
        v.x = x;
        v.z = z;
    }
    return glm::normalize(v);
}

AmbientWeights ambientWeights(glm::dvec3 n) {
    AmbientWeights w;
    for (int axis = 0; axis < 3; ++axis) {
        w.weight[std::size_t(axis)] = n[axis] * n[axis];
        w.face[std::size_t(axis)] = 2 * axis + (n[axis] < 0.0 ? 1 : 0);
    }
    return w;
}

glm::dvec3 ambientIrradiance(const AmbientCube& cube, glm::dvec3 n) {
    const AmbientWeights w = ambientWeights(n);
    glm::dvec3 e(0.0);
    for (int axis = 0; axis < 3; ++axis) e += w.weight[std::size_t(axis)] * cube.c[std::size_t(w.face[std::size_t(axis)])];
    return e;
}

AmbientCube ambientCubeFromSh(const ShRgb& radiance) {
    static const glm::dvec3 kAxes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    AmbientCube cube;
    for (std::size_t f = 0; f < 6; ++f) cube.c[f] = shIrradiance(radiance, kAxes[f]);
    return cube;
}

std::vector<glm::vec3> octIrradianceTexture(const ShRgb& radiance, int size) {
    std::vector<glm::vec3> texels;
    for (int j = 0; j < size; ++j)
        for (int i = 0; i < size; ++i) {
            const glm::dvec2 e(2.0 * (i + 0.5) / size - 1.0, 2.0 * (j + 0.5) / size - 1.0);
            texels.push_back(glm::vec3(shIrradiance(radiance, octDecode(e))));
        }
    return texels;
}

glm::dvec3 sampleOctTexture(std::span<const glm::vec3> texels, int size, glm::dvec3 n) {
    const glm::dvec2 e = octEncode(n);
    const glm::dvec2 p = (e + 1.0) * 0.5 * double(size) - 0.5;
    const int x0 = int(std::floor(p.x)), y0 = int(std::floor(p.y));
    const double fx = p.x - x0, fy = p.y - y0;
    const auto at = [&](int x, int y) {
        return glm::dvec3(texels[std::size_t(std::clamp(y, 0, size - 1) * size + std::clamp(x, 0, size - 1))]);
    };
    return glm::mix(glm::mix(at(x0, y0), at(x0 + 1, y0), fx), glm::mix(at(x0, y0 + 1), at(x0 + 1, y0 + 1), fx), fy);
}

double chebyshevVisibility(double distance, double mean, double meanSquare) {
    if (distance <= mean) return 1.0;
    const double variance = std::max(meanSquare - mean * mean, 1e-12);
    const double d = distance - mean;
    return variance / (variance + d * d);
}

}  // namespace dawnforge::runtime
