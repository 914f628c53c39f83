// The engine axes and the Labs quaternion packing (vat_codec.hpp).
#include "vat_codec.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace dawnforge::exporters::vat_codec {

Engine engineOf(VatPreset preset) {
    switch (preset) {
        case VatPreset::Native: return {};
        case VatPreset::Unity: return {glm::dmat3(-1, 0, 0, 0, 1, 0, 0, 0, 1), 1.0, -1.0};  // (-x, y, z)
        case VatPreset::Unreal: return {glm::dmat3(1, 0, 0, 0, 0, 1, 0, 1, 0), 100.0, -1.0};  // 100 (x, z, y)
    }
    return {};
}

PackedRotation pack(glm::dquat q) {
    const std::array<double, 4> c{q.w, q.x, q.y, q.z};
    int m = 0;
    for (int i = 1; i < 4; ++i)
        if (std::abs(c[std::size_t(i)]) > std::abs(c[std::size_t(m)])) m = i;
    if (c[std::size_t(m)] < 0.0) q = -q;
    PackedRotation p;
    p.dropped = m;
    p.canonical = q;
    switch (m) {
        case 0: p.triple = {q.x, q.y, q.z}; break;
        case 1: p.triple = {q.w, q.y, q.z}; break;
        case 2: p.triple = {q.x, q.w, q.z}; break;
        default: p.triple = {q.x, q.y, q.w}; break;
    }
    return p;
}

glm::dquat unpack(const glm::dvec3& t, int dropped) {
    const double rebuilt = std::sqrt(std::max(0.0, 1.0 - glm::dot(t, t)));
    switch (dropped) {
        case 0: return glm::dquat(rebuilt, t.x, t.y, t.z);
        case 1: return glm::dquat(t.x, rebuilt, t.y, t.z);
        case 2: return glm::dquat(t.y, t.x, rebuilt, t.z);
        default: return glm::dquat(t.z, t.x, t.y, rebuilt);
    }
}

double angleBetween(const glm::dquat& a, const glm::dquat& b) {
    return 2.0 * std::acos(std::min(1.0, std::abs(glm::dot(glm::normalize(a), glm::normalize(b)))));
}

}  // namespace dawnforge::exporters::vat_codec
