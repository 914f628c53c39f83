#include "gpu_checks.hpp"

#include "gl.hpp"
#include "ocean_gpu.hpp"
#include "trees.hpp"

#include <glm/gtc/type_ptr.hpp>

namespace dawnforge::runtime {

namespace {

// Runs gpu_checks.comp over `inputs`; two vec4 outputs per input.
std::vector<glm::vec4> run(int mode, const std::vector<glm::vec4>& inputs, const OceanUniforms& ocean, GLuint noise,
                           const glm::mat4& inverseViewProjection, glm::vec4 wind = glm::vec4(0.0f), int count = -1) {
    const gl::Program program = gl::makeComputeProgram("gpu_checks.comp");
    const gl::Buffer in = gl::makeBuffer(inputs);
    const gl::Buffer out = gl::makeBuffer(nullptr, inputs.size() * 2 * sizeof(glm::vec4), GL_MAP_READ_BIT);
    const gl::Buffer ubo = gl::makeBuffer(&ocean, sizeof(ocean));
    glUseProgram(program.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, in.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, out.id());
    glBindBufferBase(GL_UNIFORM_BUFFER, 2, ubo.id());
    if (noise) glBindTextureUnit(5, noise);
    glUniform1i(0, mode);
    if (count < 0) count = int(inputs.size());
    glUniform1i(1, count);
    glUniformMatrix4fv(2, 1, GL_FALSE, glm::value_ptr(inverseViewProjection));
    glUniform4fv(3, 1, glm::value_ptr(wind));
    glDispatchCompute(GLuint((count + 63) / 64), 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    std::vector<glm::vec4> result(std::size_t(count) * 2);
    glGetNamedBufferSubData(out.id(), 0, GLsizeiptr(result.size() * sizeof(glm::vec4)), result.data());
    gl::check("gpu checks");
    return result;
}

}  // namespace

std::vector<GpuWaveSample> gpuWaves(const WaveSet& waves, const WaveNoise& noise, const std::vector<glm::dvec2>& points,
                                    double t, double attenuation) {
    const gl::Texture texture = uploadWaveNoise(noise);
    std::vector<glm::vec4> inputs;
    for (const glm::dvec2& p : points) inputs.emplace_back(float(p.x), float(p.y), float(t), float(attenuation));
    const std::vector<glm::vec4> out = run(0, inputs, oceanUniforms(waves, 0.0, 1.0, 2), texture.id(), glm::mat4(1.0f));
    std::vector<GpuWaveSample> samples(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
        samples[i].displacement = glm::dvec3(out[2 * i]);
        samples[i].noiseHeight = out[2 * i].w;
        samples[i].normal = glm::dvec3(out[2 * i + 1]);
    }
    return samples;
}

std::vector<glm::dvec3> gpuGridVertices(const OceanGrid& grid) {
    if (!grid.visible) return {};
    std::vector<glm::vec4> inputs;
    for (int r = 0; r < grid.rows; ++r)
        for (int c = 0; c < grid.columns; ++c)
            inputs.emplace_back(-1.0f + 2.0f * float(c) / float(grid.columns - 1), float(grid.rowNdcY[std::size_t(r)]),
                                float(grid.level), 0.0f);
    const std::vector<glm::vec4> out =
        run(1, inputs, oceanUniforms(defaultWaves(), grid.level, 1.0, grid.columns), 0, glm::mat4(grid.inverseViewProjection));
    std::vector<glm::dvec3> vertices(inputs.size());
    for (std::size_t i = 0; i < inputs.size(); ++i) vertices[i] = glm::dvec3(out[2 * i]);
    return vertices;
}

std::vector<glm::dvec3> gpuWind(const exporters::PivotPainter& painter, const std::vector<GpuWindPoint>& points,
                                glm::dvec3 direction, double speed, double time, double phase) {
    const PivotTextures textures = uploadPivotTextures(painter);
    glBindTextureUnit(kPivotUnit, textures.pivots.id());
    glBindTextureUnit(kAxisUnit, textures.axes.id());
    // The first half of the inputs: (point, phase); the second: (uv1, time, 0).
    std::vector<glm::vec4> inputs;
    for (const GpuWindPoint& p : points) inputs.emplace_back(p.position, float(phase));
    for (const GpuWindPoint& p : points) inputs.emplace_back(p.uv1, float(time), 0.0f);
    const std::vector<glm::vec4> out = run(2, inputs, oceanUniforms(defaultWaves(), 0.0, 1.0, 2), 0, glm::mat4(1.0f),
                                           glm::vec4(glm::vec3(direction), float(speed)), int(points.size()));
    std::vector<glm::dvec3> bent(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) bent[i] = glm::dvec3(out[2 * i]);
    return bent;
}

std::vector<GpuProbeSample> gpuProbeMath(const ShRgb& sh, const AmbientCube& cube, const std::vector<glm::dvec3>& directions,
                                         const std::vector<double>& distances) {
    std::vector<glm::vec4> probe;
    for (const glm::dvec3& c : sh.c) probe.emplace_back(glm::vec3(c), 0.0f);
    for (const glm::dvec3& c : cube.c) probe.emplace_back(glm::vec3(c), 0.0f);
    const gl::Buffer buffer = gl::makeBuffer(probe);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, buffer.id());
    std::vector<glm::vec4> inputs;
    for (std::size_t i = 0; i < directions.size(); ++i) inputs.emplace_back(glm::vec3(directions[i]), float(distances[i]));
    const std::vector<glm::vec4> out = run(3, inputs, oceanUniforms(defaultWaves(), 0.0, 1.0, 2), 0, glm::mat4(1.0f));
    std::vector<GpuProbeSample> samples(directions.size());
    for (std::size_t i = 0; i < directions.size(); ++i) {
        samples[i].shIrradiance = glm::dvec3(out[2 * i]);
        samples[i].chebyshev = out[2 * i].w;
        samples[i].ambientRed = out[2 * i + 1].x;
        samples[i].oct = glm::dvec2(out[2 * i + 1].y, out[2 * i + 1].z);
        samples[i].octRoundTripY = out[2 * i + 1].w;
    }
    return samples;
}

}  // namespace dawnforge::runtime
