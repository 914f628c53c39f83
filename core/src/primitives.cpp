#include <dawnforge/core/primitives.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <utility>

namespace dawnforge {

Mesh makeBox(glm::vec3 lo, glm::vec3 hi, std::uint8_t materialId) {
    Mesh m;
    m.name = "box";
    // Each face: normal, and the two axes (u, v) with u × v = normal, so corners wind CCW.
    struct Face { glm::vec3 n, u, v; };
    const std::array<Face, 6> faces{{{{1, 0, 0}, {0, 0, -1}, {0, 1, 0}},
                                     {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
                                     {{0, 1, 0}, {1, 0, 0}, {0, 0, -1}},
                                     {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
                                     {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},
                                     {{0, 0, -1}, {-1, 0, 0}, {0, 1, 0}}}};
    const glm::vec3 centre = 0.5f * (lo + hi), half = 0.5f * (hi - lo);
    for (const Face& f : faces) {
        const auto base = static_cast<std::uint32_t>(m.positions.size());
        for (int k = 0; k < 4; ++k) {
            const float su = (k == 1 || k == 2) ? 1.0f : -1.0f, sv = (k >= 2) ? 1.0f : -1.0f;
            const glm::vec3 p = centre + half * (f.n + su * f.u + sv * f.v);
            m.positions.push_back(p);
            m.normals.push_back(f.n);
            m.uv0.emplace_back(glm::dot(p, f.u), glm::dot(p, f.v));  // metres along the face
            m.materialIds.push_back(materialId);
        }
        m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    }
    return m;
}

Mesh makeTower(int floors, float storeyHeight, float width, float depth, std::uint8_t wallMaterial,
               std::uint8_t bandMaterial) {
    Mesh m;
    m.name = "tower";
    const float hx = 0.5f * width, hz = 0.5f * depth, top = floors * storeyHeight;
    auto quad = [&](glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d, glm::vec3 n, glm::vec3 u, glm::vec3 v,
                    std::uint8_t material) {  // a, b, c, d counter-clockwise seen from outside
        const auto base = static_cast<std::uint32_t>(m.positions.size());
        for (const glm::vec3& p : {a, b, c, d}) {
            m.positions.push_back(p);
            m.normals.push_back(n);
            m.uv0.emplace_back(glm::dot(p, u), glm::dot(p, v));
            m.materialIds.push_back(material);
        }
        m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    };
    // The four sides, each as (start corner, end corner, outward normal), walking counter-clockwise from above.
    const std::array<std::array<glm::vec3, 3>, 4> sides{{{glm::vec3(-hx, 0, hz), glm::vec3(hx, 0, hz), glm::vec3(0, 0, 1)},
                                                          {glm::vec3(hx, 0, hz), glm::vec3(hx, 0, -hz), glm::vec3(1, 0, 0)},
                                                          {glm::vec3(hx, 0, -hz), glm::vec3(-hx, 0, -hz), glm::vec3(0, 0, -1)},
                                                          {glm::vec3(-hx, 0, -hz), glm::vec3(-hx, 0, hz), glm::vec3(-1, 0, 0)}}};
    const glm::vec3 up(0, 1, 0);
    for (int f = 0; f < floors; ++f) {
        const glm::vec3 y0(0, f * storeyHeight, 0), y1(0, (f + 1) * storeyHeight, 0);
        const std::uint8_t material = f % 2 ? bandMaterial : wallMaterial;
        for (const auto& [s0, s1, n] : sides)
            quad(s0 + y0, s1 + y0, s1 + y1, s0 + y1, n, glm::normalize(s1 - s0), up, material);
    }
    const glm::vec3 t(0, top, 0);
    quad(glm::vec3(-hx, 0, hz) + t, glm::vec3(hx, 0, hz) + t, glm::vec3(hx, 0, -hz) + t, glm::vec3(-hx, 0, -hz) + t, up,
         {1, 0, 0}, {0, 0, -1}, wallMaterial);
    quad(glm::vec3(-hx, 0, -hz), glm::vec3(hx, 0, -hz), glm::vec3(hx, 0, hz), glm::vec3(-hx, 0, hz), -up, {1, 0, 0},
         {0, 0, 1}, wallMaterial);
    return m;
}

Mesh makeIcosphere(float radius, int subdivisions) {
    const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
    std::vector<glm::vec3> p{{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                             {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    for (glm::vec3& v : p) v = glm::normalize(v);
    std::vector<std::uint32_t> idx{0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4,
                                   11, 10, 2, 10, 7, 6, 7, 1, 8, 3, 9, 4, 3, 4, 2, 3, 2, 6, 3, 6, 8,
                                   3, 8, 9, 4, 9, 5, 2, 4, 11, 6, 2, 10, 8, 6, 7, 9, 8, 1};
    for (int s = 0; s < subdivisions; ++s) {
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> midpoint;
        auto mid = [&](std::uint32_t a, std::uint32_t b) {
            const auto key = std::minmax(a, b);
            auto [it, inserted] = midpoint.try_emplace(key, static_cast<std::uint32_t>(p.size()));
            if (inserted) p.push_back(glm::normalize(p[a] + p[b]));
            return it->second;
        };
        std::vector<std::uint32_t> next;
        next.reserve(idx.size() * 4);
        for (std::size_t i = 0; i < idx.size(); i += 3) {
            const std::uint32_t a = idx[i], b = idx[i + 1], c = idx[i + 2];
            const std::uint32_t ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
            next.insert(next.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
        }
        idx = std::move(next);
    }
    Mesh m;
    m.name = "icosphere";
    m.indices = std::move(idx);
    for (const glm::vec3& v : p) {
        m.positions.push_back(radius * v);
        m.normals.push_back(v);
    }
    return m;
}

}  // namespace dawnforge
