#pragma once
// The shaders' functions evaluated on the GPU (a compute shader including the same GLSL
// the vertex shaders use), so tests can hold them against the CPU versions in ocean.hpp.
// A GL context must be current.
#include <dawnforge/exporters/pivot_painter.hpp>
#include <dawnforge/runtime/ocean.hpp>
#include <dawnforge/runtime/probe_math.hpp>

#include <glm/glm.hpp>

#include <vector>

namespace dawnforge::runtime {

struct GpuWaveSample {
    glm::dvec3 displacement;  // Gerstner offset from (x, 0, z)
    double noiseHeight = 0.0; // the noise texture's height detail
    glm::dvec3 normal;
};
// points: (x, z) on the plane; the same waves and noise texture the renderer uploads.
std::vector<GpuWaveSample> gpuWaves(const WaveSet& waves, const WaveNoise& noise, const std::vector<glm::dvec2>& points,
                                    double t, double attenuation);
// Every vertex of `grid` (row-major, row 0 first) as the ocean vertex shader places it before displacement.
std::vector<glm::dvec3> gpuGridVertices(const OceanGrid& grid);

// Tree-space points, each with the TEXCOORD_1 of the element that carries it, as wind.glsl
// bends them with `painter`'s textures (native preset), the wind blowing to `direction` (unit).
struct GpuWindPoint {
    glm::vec3 position;
    glm::vec2 uv1;
};
std::vector<glm::dvec3> gpuWind(const exporters::PivotPainter& painter, const std::vector<GpuWindPoint>& points,
                                glm::dvec3 direction, double speed, double time, double phase);

// probes.glsl for each direction: the SH irradiance of `sh`, the ambient cube's irradiance
// (red), octEncode and the y of octDecode(octEncode), and the Chebyshev visibility at
// `distances` from a probe that saw mean 2 and mean square 4.5.
struct GpuProbeSample {
    glm::dvec3 shIrradiance;
    double ambientRed = 0.0;
    glm::dvec2 oct;
    double octRoundTripY = 0.0;
    double chebyshev = 0.0;
};
std::vector<GpuProbeSample> gpuProbeMath(const ShRgb& sh, const AmbientCube& cube, const std::vector<glm::dvec3>& directions,
                                         const std::vector<double>& distances);

}  // namespace dawnforge::runtime
