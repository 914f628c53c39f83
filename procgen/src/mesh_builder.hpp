#pragma once
// Private to procgen: builds flat-shaded meshes face by face in plan coordinates.
#include <dawnforge/core/error.hpp>
#include <dawnforge/core/mesh.hpp>
#include <dawnforge/procgen/geometry2d.hpp>

#include <glm/geometric.hpp>

#include <cstdint>
#include <span>

namespace dawnforge::procgen {

// Flat-shaded faces with per-face vertices; the caller gives each polygon's corners in
// cyclic order and the normal it should face, and the builder winds it to match.
class MeshBuilder {
public:
    explicit MeshBuilder(Mesh& mesh) : m_(mesh) {}

    struct Uv {
        enum Kind { Wall, Plan } kind = Plan;
        glm::dvec2 dir{1.0, 0.0};  // Wall: u = dot(plan, dir) + offset, v = height
        double offset = 0.0;
    };
    // Interior-mapping data for glass: room box origin (plan point, height), its along-wall
    // direction, and the three uv sets' constants.
    struct Glass {
        glm::dvec2 origin{0.0};
        double floorY = 0.0;
        glm::dvec2 dir{1.0, 0.0};
        glm::vec2 depthIndex{0.0f};
        glm::vec2 size{0.0f};
    };

    // A convex polygon (plan points with heights), fanned from its first corner.
    void polygon(std::span<const glm::dvec3> pts, glm::dvec3 want, std::uint8_t material, const Uv& uv,
                 const Glass* glass = nullptr) {
        const std::size_t n = pts.size();
        DAWNFORGE_ASSERT(n >= 3, "fewer than three corners");
        glm::dvec3 normal(0.0);
        for (std::size_t i = 1; i + 1 < n; ++i) normal += glm::cross(world(pts[i]) - world(pts[0]), world(pts[i + 1]) - world(pts[0]));
        const bool flip = glm::dot(normal, want) < 0.0;
        const auto base = static_cast<std::uint32_t>(m_.positions.size());
        const glm::vec3 nf = glm::vec3(glm::normalize(want));
        for (std::size_t k = 0; k < n; ++k) {
            const glm::dvec3 p = pts[flip ? n - 1 - k : k];
            m_.positions.push_back(toWorld({p.x, p.y}, p.z));
            m_.normals.push_back(nf);
            m_.materialIds.push_back(material);
            if (glass) {
                m_.uv0.push_back(glm::vec2(glm::dot(glm::dvec2(p.x, p.y) - glass->origin, glass->dir), p.z - glass->floorY));
                m_.uv1.push_back(glass->depthIndex);
                m_.uv2.push_back(glass->size);
            } else {
                m_.uv0.push_back(uv.kind == Uv::Wall
                                     ? glm::vec2(glm::dot(glm::dvec2(p.x, p.y), uv.dir) + uv.offset, p.z)
                                     : glm::vec2(p.x, p.y));
                m_.uv1.emplace_back(0.0f);
                m_.uv2.emplace_back(0.0f);
            }
        }
        for (std::uint32_t k = 1; k + 1 < n; ++k) m_.indices.insert(m_.indices.end(), {base, base + k, base + k + 1});
    }
    void quad(glm::dvec3 a, glm::dvec3 b, glm::dvec3 c, glm::dvec3 d, glm::dvec3 want, std::uint8_t material,
              const Uv& uv, const Glass* glass = nullptr) {
        const glm::dvec3 pts[4] = {a, b, c, d};
        polygon(pts, want, material, uv, glass);
    }
    // A closed prism over a convex plan polygon from y0 to y1; caps fanned from the centroid
    // so that points on the sides' edges (collinear corners) stay out of degenerate triangles.
    // A closed prism over any simple counter-clockwise polygon (caps by ear clipping).
    void prismAny(std::span<const glm::dvec2> poly, double y0, double y1, std::uint8_t sideMaterial,
                  std::uint8_t topMaterial) {
        const std::vector<std::uint32_t> tris = triangulatePolygon(poly);
        for (std::size_t t = 0; t < tris.size(); t += 3) {
            const glm::dvec3 top[3] = {{poly[tris[t]], y1}, {poly[tris[t + 1]], y1}, {poly[tris[t + 2]], y1}};
            polygon(top, up(), topMaterial, {});
            const glm::dvec3 bottom[3] = {{poly[tris[t]], y0}, {poly[tris[t + 1]], y0}, {poly[tris[t + 2]], y0}};
            polygon(bottom, -up(), topMaterial, {});
        }
        for (std::size_t i = 0; i < poly.size(); ++i) {
            const glm::dvec2 a = poly[i], b = poly[(i + 1) % poly.size()];
            const glm::dvec2 d = glm::normalize(b - a);
            quad({a, y0}, {b, y0}, {b, y1}, {a, y1}, outward(d), sideMaterial, {Uv::Wall, d, 0.0});
        }
    }
    void prism(std::span<const glm::dvec2> poly, double y0, double y1, std::uint8_t sideMaterial,
               std::uint8_t topMaterial, std::uint8_t bottomMaterial) {
        const std::size_t n = poly.size();
        const glm::dvec2 c = centroid(poly);
        for (std::size_t i = 0; i < n; ++i) {
            const glm::dvec2 a = poly[i], b = poly[(i + 1) % n];
            const glm::dvec3 top[3] = {{a, y1}, {b, y1}, {c, y1}};
            polygon(top, up(), topMaterial, {});
            const glm::dvec3 bottom[3] = {{a, y0}, {b, y0}, {c, y0}};
            polygon(bottom, -up(), bottomMaterial, {});
            const glm::dvec2 d = glm::normalize(b - a);
            quad({a, y0}, {b, y0}, {b, y1}, {a, y1}, outward(d), sideMaterial, {Uv::Wall, d, 0.0});
        }
    }

    static glm::dvec3 up() { return {0.0, 1.0, 0.0}; }
    // The world normal of a counter-clockwise (seen from its front) triangle of plan points with heights.
    static glm::dvec3 faceNormal(std::span<const glm::dvec3, 3> t) {
        return glm::normalize(glm::cross(world(t[1]) - world(t[0]), world(t[2]) - world(t[0])));
    }
    // The world direction of plan direction d's outward normal (right of d), and of a plan direction.
    static glm::dvec3 outward(glm::dvec2 d) { return planDir({d.y, -d.x}); }
    static glm::dvec3 planDir(glm::dvec2 d) { return {d.x, 0.0, -d.y}; }

private:
    static glm::dvec3 world(glm::dvec3 p) { return {p.x, p.z, -p.y}; }
    Mesh& m_;
};

}  // namespace dawnforge::procgen
