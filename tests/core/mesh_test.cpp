#include <dawnforge/core/error.hpp>
#include <dawnforge/core/mesh.hpp>
#include <dawnforge/core/primitives.hpp>
#include <dawnforge/core/validate.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace dawnforge;

TEST(MaterialId, EveryIdRoundTripsThroughBinaryColor) {
    for (int id = 0; id < kMaterialIdCount; ++id) {
        const glm::u8vec4 c = materialIdToColor(std::uint8_t(id));
        for (int k = 0; k < 4; ++k) EXPECT_TRUE(c[k] == 0 || c[k] == 255);
        EXPECT_EQ(c.r / 255 + 2 * (c.g / 255) + 4 * (c.b / 255) + 8 * (c.a / 255), id);
        EXPECT_EQ(colorToMaterialId(glm::vec4(c) / 255.0f), id);
    }
}

TEST(MeshData, RejectsEachKindOfBadData) {
    const Mesh good = makeBox({0, 0, 0}, {1, 1, 1});
    EXPECT_NO_THROW(validateMeshData(good, "good"));

    auto expectRejected = [](const Mesh& m, const char* expectedText) {
        try {
            validateMeshData(m, "input.obj");
            ADD_FAILURE() << "accepted a mesh that should fail with: " << expectedText;
        } catch (const InputError& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find("input.obj"), std::string::npos) << what;
            EXPECT_NE(what.find(expectedText), std::string::npos) << what;
        }
    };
    Mesh m = good;
    m.positions[3].y = std::numeric_limits<float>::quiet_NaN();
    expectRejected(m, "non-finite");
    m = good;
    m.positions[0].z = std::numeric_limits<float>::infinity();
    expectRejected(m, "non-finite");
    m = good;
    m.indices[7] = 24;
    expectRejected(m, "only 24 vertices");
    m = good;
    m.indices.pop_back();
    expectRejected(m, "multiple of 3");
    m = good;
    m.indices.clear();
    expectRejected(m, "no triangles");
    m = good;
    m.uv0.pop_back();
    expectRejected(m, "uv0");
    m = good;
    m.materialIds[2] = 16;
    expectRejected(m, "material ID 16");
}

TEST(MeshData, BoundsCoverEveryPosition) {
    const Mesh box = makeBox({-1, 2, -3}, {4, 5, 6});
    const Bounds b = computeBounds(box.positions);
    EXPECT_EQ(b.min, glm::dvec3(-1, 2, -3));
    EXPECT_EQ(b.max, glm::dvec3(4, 5, 6));
}

TEST(AppendMesh, TransformsAndFillsMissingAttributes) {
    Mesh plain;  // positions only
    plain.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    plain.indices = {0, 1, 2};
    Mesh dst = plain;
    const Mesh box = makeBox({0, 0, 0}, {1, 1, 1}, 5);
    appendMesh(dst, box, glm::translate(glm::mat4(1.0f), glm::vec3(10, 0, 0)));
    ASSERT_EQ(dst.vertexCount(), 27u);
    ASSERT_EQ(dst.materialIds.size(), 27u);
    EXPECT_EQ(dst.materialIds[0], 0);   // filled for the plain triangle
    EXPECT_EQ(dst.materialIds[26], 5);  // kept for the box
    EXPECT_EQ(dst.normals.size(), 27u);
    EXPECT_FLOAT_EQ(computeBounds(std::span(dst.positions).subspan(3)).min.x, 10.0);
    EXPECT_EQ(dst.indices[3], 3u);
    EXPECT_NO_THROW(validateMeshData(dst, "appended"));
}

TEST(AppendMesh, MirroringKeepsTheVolumePositive) {
    Mesh mirrored;
    appendMesh(mirrored, makeBox({0, 0, 0}, {1, 2, 3}), glm::scale(glm::mat4(1.0f), glm::vec3(-1, 1, 1)));
    const MeshReport r = inspectMesh(mirrored);
    ASSERT_TRUE(r.volume.has_value());
    EXPECT_NEAR(*r.volume, 6.0, 1e-6);
    EXPECT_TRUE(r.outwardOriented);
    // Normals follow the mirror: the +X face now faces -X.
    EXPECT_FLOAT_EQ(mirrored.normals[0].x, -1.0f);
}

TEST(WeldByPosition, MapsDuplicatesToTheirFirstOccurrence) {
    const std::vector<glm::vec3> p{{0, 0, 0}, {1, 0, 0}, {0, 0, 0}, {-0.0f, 0, 0}, {1, 0, 0}, {2, 0, 0}};
    const std::vector<std::uint32_t> w = weldByPosition(p);
    EXPECT_EQ(w, (std::vector<std::uint32_t>{0, 1, 0, 0, 1, 5}));
}

TEST(FlipOrientation, NegatesVolumeAndNormals) {
    Mesh box = makeBox({0, 0, 0}, {1, 1, 1});
    flipOrientation(box);
    const MeshReport r = inspectMesh(box);
    ASSERT_TRUE(r.volume.has_value());
    EXPECT_NEAR(*r.volume, -1.0, 1e-9);
    EXPECT_FALSE(r.outwardOriented);
    EXPECT_FLOAT_EQ(box.normals[0].x, -1.0f);
}
