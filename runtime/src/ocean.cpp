// Gerstner waves, wave noise, buoyancy queries and the projected grid (see ocean.hpp for
// the sources). Mirrored in single precision by runtime/shaders/ocean_waves.glsl: a change
// to the maths here must be made there too.
#include <dawnforge/core/error.hpp>
#include <dawnforge/core/seed.hpp>
#include <dawnforge/runtime/ocean.hpp>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <numbers>

namespace dawnforge::runtime {

namespace {

// Everything one evaluation of the waves gives: the offset and the derivatives of the
// displaced point P with respect to the plane point (x, z).
struct WaveEval {
    glm::dvec3 displacement{0.0};
    glm::dvec3 dPdx{1.0, 0.0, 0.0};
    glm::dvec3 dPdz{0.0, 0.0, 1.0};
};

WaveEval evaluate(const WaveSet& set, glm::dvec2 x0, double t, double attenuation) {
    WaveEval e;
    for (const GerstnerWave& w : set.waves) {
        const double a = w.amplitude * attenuation;
        if (a == 0.0) continue;
        const double k = 2.0 * std::numbers::pi / w.wavelength;
        const double omega = std::sqrt(kOceanGravity * k);
        const double theta = k * glm::dot(w.direction, x0) - omega * t + w.phase;
        const double s = std::sin(theta), c = std::cos(theta);
        const glm::dvec2 d = w.direction;
        const double qa = w.steepness * a;
        e.displacement += glm::dvec3(qa * d.x * c, a * s, qa * d.y * c);
        // ∂θ/∂x0 = k D.
        const double qaks = qa * k * s, akc = a * k * c;
        e.dPdx += glm::dvec3(-qaks * d.x * d.x, akc * d.x, -qaks * d.x * d.y);
        e.dPdz += glm::dvec3(-qaks * d.y * d.x, akc * d.y, -qaks * d.y * d.y);
    }
    return e;
}

double horizontalJacobian(const WaveEval& e) { return e.dPdx.x * e.dPdz.z - e.dPdz.x * e.dPdx.z; }

// Lattice value in [0, 1) for one channel, octave and (wrapped) lattice point.
double latticeValue(std::uint64_t channelSeed, int octave, int ix, int iy) {
    std::uint64_t h = mix64(channelSeed ^ mix64(static_cast<std::uint64_t>(octave) + 0x100));
    h = mix64(h ^ static_cast<std::uint64_t>(static_cast<std::uint32_t>(ix)));
    h = mix64(h ^ (static_cast<std::uint64_t>(static_cast<std::uint32_t>(iy)) << 32));
    return static_cast<double>(h >> 11) * 0x1.0p-53;
}

double fade(double x) { return x * x * x * (x * (x * 6.0 - 15.0) + 10.0); }

int wrapIndex(long long i, int n) {
    const long long m = i % n;
    return static_cast<int>(m < 0 ? m + n : m);
}

}  // namespace

WaveSet defaultWaves() {
    // Wind along +x. Each wave gets the same share of Σ Q·k·A, so the steepness follows
    // from the amplitude and wavelength: Q = share / (k A).
    struct Spec { double angleDeg, wavelength, amplitude, phase; };
    constexpr std::array<Spec, 4> specs{Spec{0.0, 60.0, 0.80, 0.0}, Spec{28.0, 33.0, 0.45, 1.3},
                                        Spec{-37.0, 17.0, 0.25, 4.1}, Spec{71.0, 8.5, 0.12, 2.6}};
    constexpr double share = 0.8 / 4.0;
    WaveSet set;
    for (std::size_t i = 0; i < 4; ++i) {
        const double angle = specs[i].angleDeg * std::numbers::pi / 180.0;
        GerstnerWave& w = set.waves[i];
        w.direction = {std::cos(angle), std::sin(angle)};
        w.wavelength = specs[i].wavelength;
        w.amplitude = specs[i].amplitude;
        w.phase = specs[i].phase;
        const double k = 2.0 * std::numbers::pi / w.wavelength;
        w.steepness = share / (k * w.amplitude);
    }
    return set;
}

double foldFactor(const WaveSet& waves) {
    double sum = 0.0;
    for (const GerstnerWave& w : waves.waves) sum += w.steepness * (2.0 * std::numbers::pi / w.wavelength) * w.amplitude;
    return sum;
}

WaveSet withFoldFactor(WaveSet waves, double target) {
    const double f = foldFactor(waves);
    if (f == 0.0) return waves;
    for (GerstnerWave& w : waves.waves) w.steepness *= target / f;
    return waves;
}

WaveSample gerstner(const WaveSet& waves, glm::dvec2 x0, double t, double attenuation) {
    const WaveEval e = evaluate(waves, x0, t, attenuation);
    WaveSample s;
    s.displacement = e.displacement;
    s.normal = glm::normalize(glm::cross(e.dPdz, e.dPdx));
    s.jacobian = horizontalJacobian(e);
    return s;
}

WaveNoise makeWaveNoise(int size, std::uint64_t seed) {
    DAWNFORGE_ASSERT(size >= 1, "size must be at least 1");
    // Three octaves of periodic value noise; the lattice wraps every `cells` points, and
    // one lattice period spans the whole texture, so the texture tiles.
    constexpr std::array<double, 3> octaveWeights{0.6, 0.3, 0.1};
    const int baseCells = std::max(2, size / 16);
    WaveNoise noise;
    noise.size = size;
    noise.rgba.assign(static_cast<std::size_t>(size) * size * 4, 0.0f);
    std::vector<double> values(static_cast<std::size_t>(size) * size);
    for (int channel = 0; channel < 4; ++channel) {
        const std::uint64_t channelSeed = mix64(seed ^ mix64(0xC0FFEEull + static_cast<std::uint64_t>(channel)));
        for (int j = 0; j < size; ++j) {
            for (int i = 0; i < size; ++i) {
                double v = 0.0;
                for (int o = 0; o < 3; ++o) {
                    const int cells = baseCells << o;
                    const double px = (i + 0.5) / size * cells, py = (j + 0.5) / size * cells;
                    const double fx0 = std::floor(px), fy0 = std::floor(py);
                    const int ix = static_cast<int>(fx0) % cells, iy = static_cast<int>(fy0) % cells;
                    const int ix1 = (ix + 1) % cells, iy1 = (iy + 1) % cells;
                    const double fx = fade(px - fx0), fy = fade(py - fy0);
                    const double v00 = latticeValue(channelSeed, o, ix, iy), v10 = latticeValue(channelSeed, o, ix1, iy);
                    const double v01 = latticeValue(channelSeed, o, ix, iy1), v11 = latticeValue(channelSeed, o, ix1, iy1);
                    const double bottom = v00 + (v10 - v00) * fx, top = v01 + (v11 - v01) * fx;
                    v += octaveWeights[static_cast<std::size_t>(o)] * (bottom + (top - bottom) * fy);
                }
                values[static_cast<std::size_t>(j) * size + i] = v;
            }
        }
        // Rescale to exactly [0, 1] so every channel uses its full range.
        const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
        const double low = *lo, range = *hi - *lo;
        for (std::size_t p = 0; p < values.size(); ++p)
            noise.rgba[p * 4 + static_cast<std::size_t>(channel)] =
                range > 0.0 ? static_cast<float>((values[p] - low) / range) : 0.5f;
    }
    return noise;
}

double sampleNoise(const WaveNoise& noise, glm::dvec2 uv, int channel) {
    DAWNFORGE_ASSERT(noise.size >= 1 && noise.rgba.size() == static_cast<std::size_t>(noise.size) * noise.size * 4, "the noise texture is empty or of the wrong size");
    DAWNFORGE_ASSERT(channel >= 0 && channel < 4, "channel must be 0..3");
    const int n = noise.size;
    const double sx = uv.x * n - 0.5, sy = uv.y * n - 0.5;
    const double fx0 = std::floor(sx), fy0 = std::floor(sy);
    const double fx = sx - fx0, fy = sy - fy0;
    const int i0 = wrapIndex(static_cast<long long>(fx0), n), j0 = wrapIndex(static_cast<long long>(fy0), n);
    const int i1 = (i0 + 1) % n, j1 = (j0 + 1) % n;
    const auto texel = [&](int i, int j) {
        return static_cast<double>(noise.rgba[(static_cast<std::size_t>(j) * n + i) * 4 + static_cast<std::size_t>(channel)]);
    };
    const double bottom = texel(i0, j0) * (1.0 - fx) + texel(i1, j0) * fx;
    const double top = texel(i0, j1) * (1.0 - fx) + texel(i1, j1) * fx;
    return bottom * (1.0 - fy) + top * fy;
}

double noiseHeight(const WaveSet& waves, const WaveNoise& noise, glm::dvec2 x0, double t, double attenuation) {
    double sum = 0.0;
    for (int c = 0; c < 4; ++c) {
        const auto i = static_cast<std::size_t>(c);
        const glm::dvec2 uv = x0 * waves.noiseScale[i] + waves.noiseDrift[i] * t;
        sum += kNoiseWeights[i] * (sampleNoise(noise, uv, c) - 0.5);
    }
    return waves.noiseAmplitude * attenuation * sum;
}

SurfacePoint waterSurfaceAt(const WaveSet& waves, const WaveNoise& noise, double level, glm::dvec2 xz, double t,
                            double attenuation) {
    const auto residualOf = [&](glm::dvec2 p, WaveEval& e) {
        e = evaluate(waves, p, t, attenuation);
        return p + glm::dvec2(e.displacement.x, e.displacement.z) - xz;
    };
    glm::dvec2 x0 = xz;
    WaveEval e;
    glm::dvec2 r = residualOf(x0, e);
    const double tolerance = 1e-12 * (1.0 + std::abs(xz.x) + std::abs(xz.y));
    for (int iteration = 0; iteration < 100 && glm::length(r) > tolerance; ++iteration) {
        // Newton on F(x0) = x0 + horizontal(x0) − xz, with the analytic 2×2 Jacobian.
        const double det = horizontalJacobian(e);
        bool accepted = false;
        if (det > 1e-6) {
            const glm::dvec2 step{(e.dPdz.z * r.x - e.dPdz.x * r.y) / det, (-e.dPdx.z * r.x + e.dPdx.x * r.y) / det};
            WaveEval en;
            const glm::dvec2 candidate = x0 - step;
            const glm::dvec2 rn = residualOf(candidate, en);
            if (glm::length(rn) < glm::length(r)) {
                x0 = candidate;
                r = rn;
                e = en;
                accepted = true;
            }
        }
        if (!accepted) {
            // Fixed point x0 <- xz − horizontal(x0): contracts by Σ Q k A < 1 per step.
            x0 = x0 - r;
            r = residualOf(x0, e);
        }
    }
    SurfacePoint s;
    s.x0 = x0;
    s.height = level + e.displacement.y + noiseHeight(waves, noise, x0, t, attenuation);
    s.normal = glm::normalize(glm::cross(e.dPdz, e.dPdx));
    return s;
}

glm::dmat4 OceanCamera::view() const { return glm::lookAt(position, position + forward, glm::dvec3(0.0, 1.0, 0.0)); }

glm::dmat4 OceanCamera::projection() const { return glm::perspective(fovYRadians, aspect, nearPlane, farPlane); }

OceanGrid projectOceanGrid(const OceanCamera& camera, double level, int columns, int rows, double maxDistance,
                           double minHeight) {
    DAWNFORGE_ASSERT(columns >= 2 && rows >= 2, "columns and rows must be at least 2");
    DAWNFORGE_ASSERT(camera.nearPlane > 0.0 && camera.farPlane > camera.nearPlane, "the camera needs 0 < near < far");
    OceanGrid grid;
    grid.columns = columns;
    grid.rows = rows;
    grid.level = level;
    grid.inverseViewProjection = glm::inverse(camera.projection() * camera.view());

    const glm::dvec3 f = glm::normalize(camera.forward);
    const double sinP = f.y, cosP = std::sqrt(std::max(0.0, 1.0 - f.y * f.y));
    DAWNFORGE_ASSERT(cosP > 1e-9, "the camera must not look straight up or down");
    const double h = camera.position.y - level;
    if (!(h > 0.0)) return grid;  // at or below the water: the plane is seen edge-on or from below

    // With no roll, the ray through NDC y (any x) is f + y·tan(fov/2)·up (forward component
    // 1), so its vertical component is sinP + y·tanHalf·cosP and the plane point it meets
    // has eye depth h / −(that).
    const double tanHalf = std::tan(camera.fovYRadians * 0.5);
    const auto depthAt = [&](double ndcY) {
        const double dy = sinP + ndcY * tanHalf * cosP;
        return dy < 0.0 ? h / -dy : std::numeric_limits<double>::infinity();
    };
    const auto ndcYAt = [&](double depth) { return std::clamp((-h / depth - sinP) / (tanHalf * cosP), -1.0, 1.0); };

    const double bottom = depthAt(-1.0);
    if (!std::isfinite(bottom)) return grid;  // the whole screen is above the horizon
    constexpr double inside = 1e-7;           // keep the end rows strictly inside the clip volume
    const double nearDepth = std::max(bottom, camera.nearPlane * (1.0 + inside));
    const double farDepth = std::min({maxDistance, depthAt(1.0), camera.farPlane * (1.0 - inside)});
    if (!(farDepth > nearDepth)) return grid;

    // Geometric spacing in depth as seen from a camera at least minHeight up.
    const double offset = std::max(0.0, minHeight - h);
    const double m0 = nearDepth + offset, ratio = (farDepth + offset) / m0;
    grid.rowNdcY.resize(static_cast<std::size_t>(rows));
    grid.rowDepth.resize(static_cast<std::size_t>(rows));
    for (int r = 0; r < rows; ++r) {
        double depth = m0 * std::pow(ratio, static_cast<double>(r) / (rows - 1)) - offset;
        if (r == 0) depth = nearDepth;
        if (r == rows - 1) depth = farDepth;
        grid.rowDepth[static_cast<std::size_t>(r)] = depth;
        grid.rowNdcY[static_cast<std::size_t>(r)] = r == 0 && nearDepth == bottom ? -1.0 : ndcYAt(depth);
    }
    grid.visible = true;
    return grid;
}

glm::dvec2 oceanGridNdc(const OceanGrid& grid, int column, int row) {
    DAWNFORGE_ASSERT(column >= 0 && column < grid.columns && row >= 0 && row < static_cast<int>(grid.rowNdcY.size()), "vertex outside the grid (or the grid is not visible)");
    return {-1.0 + 2.0 * column / (grid.columns - 1), grid.rowNdcY[static_cast<std::size_t>(row)]};
}

glm::dvec3 oceanGridVertex(const OceanGrid& grid, int column, int row) {
    const glm::dvec2 ndc = oceanGridNdc(grid, column, row);
    const glm::dvec4 a = grid.inverseViewProjection * glm::dvec4(ndc, -1.0, 1.0);
    const glm::dvec4 b = grid.inverseViewProjection * glm::dvec4(ndc, 1.0, 1.0);
    const glm::dvec3 p0 = glm::dvec3(a) / a.w, p1 = glm::dvec3(b) / b.w;
    const glm::dvec3 d = p1 - p0;
    const double s = (grid.level - p0.y) / d.y;
    return p0 + s * d;
}

std::vector<float> oceanGridNdcBuffer(const OceanGrid& grid) {
    std::vector<float> out;
    if (!grid.visible) return out;
    out.reserve(static_cast<std::size_t>(grid.columns) * grid.rows * 2);
    for (int r = 0; r < grid.rows; ++r) {
        for (int c = 0; c < grid.columns; ++c) {
            const glm::dvec2 ndc = oceanGridNdc(grid, c, r);
            out.push_back(static_cast<float>(ndc.x));
            out.push_back(static_cast<float>(ndc.y));
        }
    }
    return out;
}

std::vector<std::uint32_t> oceanGridIndices(int columns, int rows) {
    DAWNFORGE_ASSERT(columns >= 2 && rows >= 2, "columns and rows must be at least 2");
    std::vector<std::uint32_t> indices;
    indices.reserve(static_cast<std::size_t>(columns - 1) * (rows - 1) * 6);
    for (int r = 0; r + 1 < rows; ++r) {
        for (int c = 0; c + 1 < columns; ++c) {
            // Bottom-left, bottom-right, top-right, top-left on screen; columns grow to the
            // right and rows away from the camera, so this is counter-clockwise from above.
            const auto bl = static_cast<std::uint32_t>(r * columns + c);
            const std::uint32_t br = bl + 1, tl = bl + static_cast<std::uint32_t>(columns), tr = tl + 1;
            indices.insert(indices.end(), {bl, br, tr, bl, tr, tl});
        }
    }
    return indices;
}

OceanWavesGpu packForGpu(const WaveSet& waves) {
    OceanWavesGpu g;
    const auto& w = waves.waves;
    g.dirs01 = {float(w[0].direction.x), float(w[0].direction.y), float(w[1].direction.x), float(w[1].direction.y)};
    g.dirs23 = {float(w[2].direction.x), float(w[2].direction.y), float(w[3].direction.x), float(w[3].direction.y)};
    for (std::size_t i = 0; i < 4; ++i) {
        g.amplitude[i] = float(w[i].amplitude);
        g.wavelength[i] = float(w[i].wavelength);
        g.steepness[i] = float(w[i].steepness);
        g.phase[i] = float(w[i].phase);
        g.noiseScale[i] = float(waves.noiseScale[i]);
        g.noiseDriftX[i] = float(waves.noiseDrift[i].x);
        g.noiseDriftY[i] = float(waves.noiseDrift[i].y);
    }
    g.noiseAmplitude = float(waves.noiseAmplitude);
    return g;
}

}  // namespace dawnforge::runtime
