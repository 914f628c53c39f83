// The runtime's wind (wind.glsl), run on llvmpipe in a compute shader over a generated tree
// species' Pivot Painter data: no wind moves nothing, and at any speed every element turns
// rigidly about its own pivot, which its parent carries.
#include <dawnforge/exporters/pivot_painter.hpp>
#include <dawnforge/procgen/dressing.hpp>
#include "gpu_checks.hpp"
#include "render_support.hpp"

#include <gtest/gtest.h>

#include <map>

using namespace dawnforge;
using namespace dawnforge::runtime;

namespace {

// The texel centre of element i, as TEXCOORD_1 holds it.
glm::vec2 texelOf(const exporters::PivotPainter& pp, int i) {
    return {(float(i % pp.width) + 0.5f) / float(pp.width), (float(i / pp.width) + 0.5f) / float(pp.height)};
}
int elementOf(const exporters::PivotPainter& pp, glm::vec2 uv) {
    return int(uv.x * float(pp.width)) + int(uv.y * float(pp.height)) * pp.width;
}

struct WindCase {
    exporters::PivotPainter pp;
    std::vector<GpuWindPoint> points;  // every vertex, then per element its pivot as its own and as its parent's
    std::size_t vertices = 0;
};

WindCase windCase(int species) {
    const procgen::TreeSpecies s = procgen::makeTreeSpecies({}, 9)[std::size_t(species)];
    WindCase c{exporters::buildPivotPainter(procgen::speciesNodes(s), exporters::PivotPreset::Native, s.name), {}, 0};
    for (std::size_t v = 0; v < c.pp.mesh.positions.size(); ++v) c.points.push_back({c.pp.mesh.positions[v], c.pp.mesh.uv1[v]});
    c.vertices = c.points.size();
    for (std::size_t e = 0; e < c.pp.elements.size(); ++e) {
        const glm::vec3 pivot(c.pp.elements[e].pivot);
        c.points.push_back({pivot, texelOf(c.pp, int(e))});
        c.points.push_back({pivot, texelOf(c.pp, c.pp.elements[e].parent)});
    }
    return c;
}

TEST(Wind, NoWindLeavesEveryVertexWhereTheMeshHasIt) {
    test::llvmpipeContext();
    const WindCase c = windCase(0);
    const std::vector<glm::dvec3> out = gpuWind(c.pp, c.points, {1, 0, 0}, 0.0, 3.7, 0.4);
    ASSERT_EQ(out.size(), c.points.size());
    for (std::size_t i = 0; i < out.size(); ++i) ASSERT_EQ(glm::vec3(out[i]), c.points[i].position) << i;
}

TEST(Wind, EveryElementTurnsRigidlyAboutItsOwnPivotWhichItsParentCarries) {
    test::llvmpipeContext();
    const glm::dvec3 wind = glm::normalize(glm::dvec3(1.0, 0.0, 0.3));
    for (int species = 0; species < 3; ++species) {
        const WindCase c = windCase(species);
        for (double speed : {3.0, 20.0}) {
            const std::vector<glm::dvec3> out = gpuWind(c.pp, c.points, wind, speed, 1.3, 0.8);
            // A vertex at a pivot moves with the parent: as the element's and as its parent's, the same point.
            for (std::size_t e = 0; e < c.pp.elements.size(); ++e) {
                const glm::dvec3 own = out[c.vertices + 2 * e], carried = out[c.vertices + 2 * e + 1];
                EXPECT_LT(glm::length(own - carried), 1e-4) << c.pp.elements[e].name << " at " << speed << " m/s";
            }
            EXPECT_LT(glm::length(out[c.vertices] - c.pp.elements[0].pivot), 1e-5) << "the trunk's foot stays put";
            // Rigid: distances between vertices of one element keep their lengths.
            std::map<int, std::size_t> first;
            double moved = 0.0, downwind = 0.0;
            for (std::size_t v = 0; v < c.vertices; ++v) {
                const int e = elementOf(c.pp, c.points[v].uv1);
                const auto [it, added] = first.try_emplace(e, v);
                const glm::dvec3 a(c.points[v].position), b(c.points[it->second].position);
                EXPECT_NEAR(glm::length(out[v] - out[it->second]), glm::length(a - b), 2e-4) << "element " << e;
                moved = std::max(moved, glm::length(out[v] - a));
                downwind += glm::dot(out[v] - a, wind);
            }
            EXPECT_GT(moved, 0.02 * speed) << "the crown sways";
            EXPECT_GT(downwind, 0.0) << "it leans the way the wind blows";
        }
    }
}

}  // namespace
