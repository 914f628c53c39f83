#pragma once
// Ocean surface: a sum of four Gerstner waves plus a tileable noise texture for detail,
// drawn on a projected (screen-space) grid.
//
// Gerstner waves follow Tessendorf, "Simulating Ocean Water" (SIGGRAPH course, 2001) and
// Finch, "Effective Water Simulation from Physical Models" (GPU Gems, ch. 1, 2004), with
// the steepness Q kept dimensionless: a wave moves points horizontally by Q·A·D·cos θ, and
// the horizontal map x0 -> x0 + Σ Q A D cos θ is one-to-one (the surface never folds) when
// Σ Q·k·A ≤ 1. The projected grid follows Johanson, "Real-time water rendering: introducing
// the projected grid concept" (MSc thesis, Lund, 2004), with rows spaced geometrically in
// distance instead of uniformly on screen.
//
// The GPU side is runtime/shaders/ocean_waves.glsl: the same maths in single precision,
// called by a vertex shader with the parameters packed as documented at OceanWavesGpu.
// CPU maths is in doubles; everything here is pure and deterministic.
#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <array>
#include <cstdint>
#include <vector>

namespace dawnforge::runtime {

inline constexpr double kOceanGravity = 9.81;  // m/s^2; ω = sqrt(g k) (deep water)

struct GerstnerWave {
    glm::dvec2 direction{1, 0};  // unit, in the xz plane (x, z)
    double amplitude = 0.5;      // A (m)
    double wavelength = 20.0;    // L (m): k = 2π/L, ω = sqrt(g k)
    double steepness = 0.5;      // Q (dimensionless). Σ Q·k·A ≤ 1 keeps the surface from folding
    double phase = 0.0;          // radians
};

struct WaveSet {
    std::array<GerstnerWave, 4> waves;
    double noiseAmplitude = 0.08;                                  // m, detail from the noise texture (height only)
    std::array<double, 4> noiseScale{1.0 / 37.0, 1.0 / 17.0, 1.0 / 7.3, 1.0 / 3.1};  // texture repeats per metre, per channel
    std::array<glm::dvec2, 4> noiseDrift{glm::dvec2{0.011, 0.004}, glm::dvec2{-0.009, 0.017},
                                         glm::dvec2{0.031, -0.012}, glm::dvec2{-0.020, -0.043}};  // uv per second
};

// Four waves from different directions (within ±75° of the wind along +x), wavelengths
// 8.5–60 m, each contributing 0.2 to Σ Q·k·A = 0.8.
WaveSet defaultWaves();

// Σ Q·k·A over the four waves: ≤ 1 means the surface never folds.
double foldFactor(const WaveSet& waves);

// The same waves with every steepness scaled so that foldFactor() == target (a set with
// foldFactor 0 is returned unchanged).
WaveSet withFoldFactor(WaveSet waves, double target);

// The Gerstner part at the plane point x0 = (x, z), time t (s). θ_i = k_i (D_i·x0) − ω_i t + phase_i,
// every amplitude multiplied by `attenuation` (shore attenuation, 0..1).
// displacement: the offset from (x, 0, z), i.e. the surface point is
//   P = (x + Σ Q A Dx cos θ, Σ A sin θ, z + Σ Q A Dz cos θ) = (x, 0, z) + displacement.
// normal: unit, upward, normalize(∂P/∂z × ∂P/∂x).
// jacobian: det of ∂(P.x, P.z)/∂(x, z); ≤ 0 where the surface folds (use for foam).
struct WaveSample {
    glm::dvec3 displacement{0.0};
    glm::dvec3 normal{0.0, 1.0, 0.0};
    double jacobian = 1.0;
};
WaveSample gerstner(const WaveSet& waves, glm::dvec2 x0, double t, double attenuation = 1.0);

// The noise texture: 4 independent channels of periodic value noise (three octaves,
// hashed lattice, quintic fade), size×size texels, tileable, deterministic for the seed,
// each channel rescaled to exactly [0, 1]. Stored RGBA float, row-major, row 0 first:
// texel (i, j) = column i (u), row j (v), at rgba[(j*size + i)*4 + channel]. Upload as-is
// (glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, size, size, 0, GL_RGBA, GL_FLOAT, rgba)), with
// GL_REPEAT on s and t and GL_LINEAR min and mag filters (no mipmaps are needed: the shader
// samples level 0).
struct WaveNoise {
    int size = 0;
    std::vector<float> rgba;
};
WaveNoise makeWaveNoise(int size = 64, std::uint64_t seed = 1);

// Bilinear with wrap, as GL samples a GL_LINEAR/GL_REPEAT texture at uv, level 0: texel
// centres at ((i+0.5)/size, (j+0.5)/size). (GPUs quantise the blend weights, typically to
// 8 bits, so a GPU sample differs from this by up to about 1/256 of a texel step.)
double sampleNoise(const WaveNoise& noise, glm::dvec2 uv, int channel);

// Fixed weights of the noise channels in noiseHeight(): the coarse channel dominates.
inline constexpr std::array<double, 4> kNoiseWeights{0.4, 0.3, 0.2, 0.1};

// noiseAmplitude * attenuation * Σ_c kNoiseWeights[c] * (sampleNoise(uv_c, c) − 0.5),
// uv_c = x0 * noiseScale[c] + noiseDrift[c] * t. Height only (no horizontal motion).
double noiseHeight(const WaveSet& waves, const WaveNoise& noise, glm::dvec2 x0, double t, double attenuation = 1.0);

// Buoyancy query: the water surface above the world point xz = (x, z). Finds the plane
// point x0 with x0 + horizontal displacement(x0) = xz (Newton steps with the analytic
// Jacobian, falling back to the fixed-point step x0 <- xz − horizontal(x0), which contracts
// since Σ Q k A < 1), then height = level + vertical displacement + noiseHeight at x0.
// The normal is the Gerstner normal (the noise is detail for shading only).
struct SurfacePoint {
    double height = 0.0;
    glm::dvec3 normal{0.0, 1.0, 0.0};
    glm::dvec2 x0{0.0};  // the plane point whose displaced position lies above xz
};
SurfacePoint waterSurfaceAt(const WaveSet& waves, const WaveNoise& noise, double level, glm::dvec2 xz, double t,
                            double attenuation = 1.0);

// The camera of the projected grid: up is +Y, no roll; forward must not be vertical.
struct OceanCamera {
    glm::dvec3 position{0.0};
    glm::dvec3 forward{0.0, 0.0, -1.0};  // unit
    double fovYRadians = 1.0471975511965976;
    double aspect = 16.0 / 9.0;
    double nearPlane = 0.1;
    double farPlane = 5000.0;
    glm::dmat4 view() const;        // glm::lookAt(position, position + forward, +Y)
    glm::dmat4 projection() const;  // glm::perspective (OpenGL: clip z in [-w, w])
};

// A screen-space grid over the water plane y = level.
//
// Rows are lines of constant eye depth (distance along the view axis): with no roll, every
// point of the plane seen at one NDC y has the same depth, so "the distance of a row" is
// its depth. Row 0 is at the bottom edge of the screen, or at the near plane when the
// plane point at the bottom edge is nearer than that (the nearest visible plane point). The
// last row is at depth min(maxDistance, where the top screen edge meets the plane, just
// inside the far plane): always strictly below the horizon. Between them the depths are
// spaced geometrically in (depth + max(0, minHeight − camera height)): a virtual camera at
// least minHeight above the water decides the spacing, so a camera skimming the water
// does not spend its rows on the first centimetres; each row's NDC y is where its depth
// projects in the real camera. Columns are uniform in NDC x from −1 to 1.
struct OceanGrid {
    bool visible = false;         // false when no part of the water plane is in view (camera at or below level, or looking up)
    int columns = 0, rows = 0;    // vertices per row / number of rows
    std::vector<double> rowNdcY;  // NDC y of each row, ascending: row 0 is the lowest on screen
    std::vector<double> rowDepth; // eye depth (m) of each row, ascending
    glm::dmat4 inverseViewProjection{1.0};
    double level = 0.0;
};
// columns, rows ≥ 2.
OceanGrid projectOceanGrid(const OceanCamera& camera, double level, int columns, int rows, double maxDistance = 2000.0,
                           double minHeight = 2.0);

// NDC of vertex (column, row): (−1 + 2·column/(columns−1), rowNdcY[row]).
glm::dvec2 oceanGridNdc(const OceanGrid& grid, int column, int row);

// The undisplaced vertex: the ray through oceanGridNdc() of the real camera (the points at
// NDC z = −1 and z = 1, through inverseViewProjection) intersected with the plane y = level.
glm::dvec3 oceanGridVertex(const OceanGrid& grid, int column, int row);

// Per-vertex NDC (x, y) as floats, vertex index = row·columns + column: the vertex buffer
// for a shader that calls oceanGridVertex() on the GPU.
std::vector<float> oceanGridNdcBuffer(const OceanGrid& grid);

// Triangles of the grid (vertex index = row·columns + column), counter-clockwise seen from
// above the water, ordered row by row: every triangle of row r (between rows r and r+1)
// comes before every triangle of row r+1, so with depth writes on, farther water (higher on
// screen, drawn later) behind nearer water fails the depth test. (columns−1)(rows−1)·6 indices.
std::vector<std::uint32_t> oceanGridIndices(int columns, int rows);

// The waves packed for runtime/shaders/ocean_waves.glsl (set these as uniforms):
//   dirs01 = (D0.x, D0.z, D1.x, D1.z), dirs23 = (D2.x, D2.z, D3.x, D3.z),
//   amplitude, wavelength, steepness, phase = (wave 0, 1, 2, 3) of each,
//   noiseAmplitude, noiseScale = (channel 0..3), noiseDriftX / noiseDriftY = drift.x / drift.y of channels 0..3.
struct OceanWavesGpu {
    std::array<float, 4> dirs01{}, dirs23{}, amplitude{}, wavelength{}, steepness{}, phase{};
    float noiseAmplitude = 0.0f;
    std::array<float, 4> noiseScale{}, noiseDriftX{}, noiseDriftY{};
};
OceanWavesGpu packForGpu(const WaveSet& waves);

}  // namespace dawnforge::runtime
