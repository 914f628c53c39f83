#pragma once
// The arithmetic of irradiance probes (issue 14), on the CPU: what the probe shaders will
// compute, and what their tests and the CPU reference hold them against.
//
// - Spherical harmonics up to L2 (9 real coefficients per channel), the basis and the
//   Lambertian convolution of Ramamoorthi & Hanrahan (2001): irradiance
//   E(n) = Σ_l A_l Σ_m L_lm Y_lm(n) with A = (π, 2π/3, π/4).
// - Projection of a cube-map capture: every texel weighted by its exact solid angle.
// - The ambient cube: six irradiance colours along ±X, ±Y, ±Z, blended by n_i² (the weights
//   sum to 1 for a unit n), and its storage as a small octahedral texture sampled by normal.
// - The octahedral map of the unit sphere onto [-1, 1]² (Cigolle et al. 2014).
// - Chebyshev visibility from a probe's depth moments (DDGI, Majercik et al. 2019).
// Directions are unit vectors in glTF axes (+Y up).
#include <glm/glm.hpp>

#include <array>
#include <span>
#include <vector>

namespace dawnforge::runtime {

inline constexpr int kShCoefficients = 9;
using Sh9 = std::array<double, kShCoefficients>;

// Radiance (or irradiance) in SH, one Sh9 per colour channel.
struct ShRgb {
    std::array<glm::dvec3, kShCoefficients> c{};
    ShRgb& operator+=(const ShRgb& o);
};

// The nine real SH basis functions at unit direction d (order: Y00; Y1-1, Y10, Y11; Y2-2 .. Y22).
Sh9 shBasis(glm::dvec3 d);
// The Lambertian convolution constant of band l (0, 1 or 2): π, 2π/3, π/4.
double shLambert(int band);

// The coefficients of a light of `radiance` arriving from unit direction d alone (a delta).
ShRgb shDirectional(glm::dvec3 d, glm::dvec3 radiance);
// Irradiance at a surface of unit normal n under the radiance `sh`.
glm::dvec3 shIrradiance(const ShRgb& radiance, glm::dvec3 n);

// Cube maps: face f in the order +X, -X, +Y, -Y, +Z, -Z; texel (x, y) of a size² face, row 0
// at the top, as OpenGL's cube map convention lays them out.
glm::dvec3 cubeTexelDirection(int face, int x, int y, int size);
// The exact solid angle a texel covers (the six faces of `size`² texels sum to 4π).
double cubeTexelSolidAngle(int x, int y, int size);
// The SH of a captured radiance cube map: faces[f][y * size + x].
ShRgb shProjectCube(const std::array<std::vector<glm::vec3>, 6>& faces, int size);

// Octahedral map: unit direction ↔ point of [-1, 1]² (the lower hemisphere folded outwards).
glm::dvec2 octEncode(glm::dvec3 d);
glm::dvec3 octDecode(glm::dvec2 e);

// Ambient cube: irradiance along +X, -X, +Y, -Y, +Z, -Z.
struct AmbientCube {
    std::array<glm::dvec3, 6> c{};
};
// The weights n_i² of the three faces n leans towards (they sum to 1 for a unit n), and
// the faces: 0/1 for ±X, 2/3 for ±Y, 4/5 for ±Z.
struct AmbientWeights {
    std::array<double, 3> weight{};
    std::array<int, 3> face{};
};
AmbientWeights ambientWeights(glm::dvec3 n);
glm::dvec3 ambientIrradiance(const AmbientCube& cube, glm::dvec3 n);
// The ambient cube of radiance `sh`: the SH irradiance along each axis.
AmbientCube ambientCubeFromSh(const ShRgb& radiance);

// An octahedral irradiance texture of size² texels (the seed stores the ambient cube as a
// 5 × 5 one): texel centres decoded to directions, each holding `sh`'s irradiance there.
std::vector<glm::vec3> octIrradianceTexture(const ShRgb& radiance, int size);
// A bilinear sample of such a texture at the direction n (edges clamped).
glm::dvec3 sampleOctTexture(std::span<const glm::vec3> texels, int size, glm::dvec3 n);

// Chebyshev's bound on the chance that a point at `distance` from a probe is visible from it,
// given the mean and mean square of the distances the probe saw that way: 1 when distance ≤
// mean, else variance / (variance + (distance − mean)²).
double chebyshevVisibility(double distance, double mean, double meanSquare);

}  // namespace dawnforge::runtime
