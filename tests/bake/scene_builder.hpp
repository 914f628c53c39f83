#pragma once
// Small hand-made receivers for the bake's tests: quads with the normal they should face,
// charted and packed the way bake/ charts a city.
#include <dawnforge/bake/charts.hpp>
#include <dawnforge/bake/lighting.hpp>

#include <glm/geometric.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace dawnforge::test {

struct ReceiverBuilder {
    std::string name = "receiver";
    std::vector<glm::vec3> positions;
    std::vector<std::uint32_t> indices;
    std::vector<std::uint8_t> materials, occluder;
    std::vector<float> texel, rayOffset;
    bake::LightmapLayout layout;

    // A parallelogram from `corner` along `a` and `b`, facing `facing` (its triangles are
    // wound so that their normal agrees with it).
    void quad(glm::vec3 corner, glm::vec3 a, glm::vec3 b, glm::vec3 facing, float texelMetres, std::uint8_t material = 3) {
        if (glm::dot(glm::cross(a, b), facing) < 0.0f) std::swap(a, b);
        const auto base = std::uint32_t(positions.size());
        positions.insert(positions.end(), {corner, corner + a, corner + a + b, corner + b});
        indices.insert(indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
        for (int k = 0; k < 2; ++k) {
            materials.push_back(material);
            occluder.push_back(1);
            texel.push_back(texelMetres);
            rayOffset.push_back(0.001f);
        }
    }

    // The inside of the box [lo, hi] (normals inward), without the faces whose flag is false:
    // open[0..5] = -x, +x, -y, +y, -z, +z.
    void room(glm::vec3 lo, glm::vec3 hi, float texelMetres, const bool (&open)[6] = {}) {
        const glm::vec3 d = hi - lo;
        const glm::vec3 x(d.x, 0, 0), y(0, d.y, 0), z(0, 0, d.z);
        if (!open[0]) quad(lo, y, z, {1, 0, 0}, texelMetres);
        if (!open[1]) quad(lo + x, y, z, {-1, 0, 0}, texelMetres);
        if (!open[2]) quad(lo, x, z, {0, 1, 0}, texelMetres, 12);
        if (!open[3]) quad(lo + y, x, z, {0, -1, 0}, texelMetres);
        if (!open[4]) quad(lo, x, y, {0, 0, 1}, texelMetres);
        if (!open[5]) quad(lo + z, x, y, {0, 0, -1}, texelMetres);
    }

    bake::ChartMesh chartMesh() const { return bake::ChartMesh{positions, indices, texel}; }

    bake::ReceiverInput input(std::uint32_t rooms = 0) {
        const bake::ChartMesh mesh = chartMesh();
        layout = bake::packLightmap(mesh, bake::makeCharts(mesh), {}, name);
        return bake::ReceiverInput{name, positions, indices, materials, occluder, rayOffset, layout, rooms};
    }
};

}  // namespace dawnforge::test
