// The runtime's wind (wind.glsl), run on llvmpipe in a compute shader over a generated tree
// species' Pivot Painter data: no wind moves nothing, and at any speed every element turns
// rigidly about its own pivot, which its parent carries. And a generated street with its
// trees and lamps, by day and by night, against golden images (golden.hpp's tolerance).
#include <dawnforge/exporters/gltf.hpp>
#include <dawnforge/exporters/pivot_painter.hpp>
#include <dawnforge/procgen/city.hpp>
#include <dawnforge/procgen/dressing.hpp>
#include <dawnforge/runtime/renderer.hpp>
#include "golden.hpp"
#include "gpu_checks.hpp"
#include "render_support.hpp"

#include <nlohmann/json.hpp>

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
    const procgen::TreeSpecies s = procgen::makeTreeSpecies(9)[std::size_t(species)];
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

// A small generated district; the camera stands in the street 15 m from its first lamp,
// looking at the lamp head, with the trees and lamps of that sidewalk in view.
TEST(Trees, DressedStreetByDayAndByNight) {
    test::llvmpipeContext();
    test::TempDir dir;
    procgen::CitySettings settings;
    settings.size = {160.0, 120.0};
    settings.seed = 3;
    procgen::City city = procgen::generateCity(settings);
    const nlohmann::json report = nlohmann::json::parse(procgen::cityReportJson(city));
    test::writeText(dir / "city.json", report.dump());
    exporters::writeGlb(procgen::takeCityScene(city), dir / "city.glb");
    ASSERT_FALSE(report["lamps"].empty());
    const nlohmann::json& lamp = report["lamps"][0];
    const glm::dvec3 light(lamp["light"][0].get<double>(), lamp["light"][2].get<double>(), -lamp["light"][1].get<double>());
    const glm::dvec3 foot(lamp["foot"][0].get<double>(), 0.0, -lamp["foot"][1].get<double>());
    const glm::dvec3 over = glm::normalize(glm::dvec3(light.x - foot.x, 0.0, light.z - foot.z));  // towards the street
    const glm::dvec3 along(-over.z, 0.0, over.x);
    SceneFile scene;
    scene.cityDir = dir.path();
    scene.time = 1.0;
    RendererOptions options;
    options.size = {160, 120};
    options.shadowMapSize = 1024;
    Renderer renderer(scene, options);
    for (const auto& [name, hours] : {std::pair{"dressed_street_day", 15.0}, std::pair{"dressed_street_night", 22.0}}) {
        FrameSettings frame = test::lookingAt(light + 4.0 * over + 15.0 * along + glm::dvec3(0.0, -2.0, 0.0), light, hours, 60.0);
        frame.time = 1.0;
        renderer.render(frame);
        test::expectGolden(name, renderer.readPixels());
    }
}

}  // namespace
