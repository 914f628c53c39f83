#include "hull.hpp"

#include <LinearMath/btConvexHullComputer.h>

#include <algorithm>
#include <limits>

namespace dawnforge::sim {

Hull buildHull(const RigidPiece& piece, const glm::dmat3& axes, int budget, double margin) {
    std::vector<btScalar> coords;
    coords.reserve(piece.mesh.positions.size() * 3);
    const glm::dmat3 toBody = glm::transpose(axes);
    for (const glm::vec3& p : piece.mesh.positions) {
        const glm::dvec3 b = toBody * glm::dvec3(p);
        coords.insert(coords.end(), {btScalar(b.x), btScalar(b.y), btScalar(b.z)});
    }
    Hull hull;
    btConvexHullComputer computer;
    const btScalar shrunk = computer.compute(coords.data(), int(3 * sizeof(btScalar)), int(coords.size() / 3),
                                             btScalar(margin), btScalar(0.25));
    std::vector<btVector3> all;
    if (shrunk >= 0 && computer.vertices.size() >= 4) {
        for (int i = 0; i < computer.vertices.size(); ++i) all.push_back(computer.vertices[i]);
        hull.margin = std::max(shrunk, btScalar(1e-4));
    } else {  // a flat or tiny piece: keep its points, a small margin
        for (std::size_t i = 0; i + 2 < coords.size(); i += 3) all.emplace_back(coords[i], coords[i + 1], coords[i + 2]);
        hull.margin = btScalar(1e-4);
    }
    if (int(all.size()) <= budget) {
        hull.points = std::move(all);
        return hull;
    }
    std::vector<btScalar> nearest(all.size(), std::numeric_limits<btScalar>::max());
    std::size_t pick = 0;
    for (std::size_t i = 1; i < all.size(); ++i)
        if (all[i].length2() > all[pick].length2()) pick = i;
    for (int n = 0; n < budget; ++n) {
        hull.points.push_back(all[pick]);
        std::size_t next = 0;
        btScalar best = -1;
        for (std::size_t i = 0; i < all.size(); ++i) {
            nearest[i] = std::min(nearest[i], (all[i] - all[pick]).length2());
            if (nearest[i] > best) { best = nearest[i]; next = i; }
        }
        pick = next;
    }
    return hull;
}

std::unique_ptr<ColliderShape> colliderShape(const Mesh& mesh) {
    auto c = std::make_unique<ColliderShape>();
    c->indices.assign(mesh.indices.begin(), mesh.indices.end());
    for (const glm::vec3& v : mesh.positions) c->vertices.insert(c->vertices.end(), {v.x, v.y, v.z});
    c->array = std::make_unique<btTriangleIndexVertexArray>(int(c->indices.size() / 3), c->indices.data(),
                                                            int(3 * sizeof(int)), int(mesh.positions.size()),
                                                            c->vertices.data(), int(3 * sizeof(btScalar)));
    c->shape = std::make_unique<btBvhTriangleMeshShape>(c->array.get(), true);
    return c;
}

}  // namespace dawnforge::sim
