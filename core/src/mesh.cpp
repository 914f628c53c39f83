#include <dawnforge/core/error.hpp>
#include <dawnforge/core/mesh.hpp>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/gtc/matrix_inverse.hpp>

#include <cmath>
#include <cstring>
#include <dawnforge/core/format.hpp>
#include <unordered_map>

namespace dawnforge {

glm::u8vec4 materialIdToColor(std::uint8_t id) {
    DAWNFORGE_ASSERT(id < kMaterialIdCount, "material ID above 15");
    return {(id & 1) ? 255 : 0, (id & 2) ? 255 : 0, (id & 4) ? 255 : 0, (id & 8) ? 255 : 0};
}

std::uint8_t colorToMaterialId(glm::vec4 rgba) {
    return static_cast<std::uint8_t>((rgba.r >= 0.5f ? 1 : 0) | (rgba.g >= 0.5f ? 2 : 0) |
                                     (rgba.b >= 0.5f ? 4 : 0) | (rgba.a >= 0.5f ? 8 : 0));
}

Bounds computeBounds(std::span<const glm::vec3> positions) {
    Bounds b;
    if (positions.empty()) return b;
    b.min = b.max = glm::dvec3(positions[0]);
    for (const glm::vec3& p : positions) {
        b.min = glm::min(b.min, glm::dvec3(p));
        b.max = glm::max(b.max, glm::dvec3(p));
    }
    return b;
}

namespace {

template <typename T>
void checkAttributeSize(const std::vector<T>& attribute, std::size_t vertices, std::string_view source,
                        std::string_view name) {
    if (!attribute.empty() && attribute.size() != vertices)
        throw InputError(format("{}: {} has {} entries for {} vertices", source, name, attribute.size(),
                                     vertices));
}

template <typename T>
void resizeAttribute(std::vector<T>& attribute, std::size_t oldSize, std::size_t newSize, bool otherHasIt) {
    if (attribute.empty() && !otherHasIt) return;
    if (attribute.empty()) attribute.assign(oldSize, T{});
    attribute.resize(newSize, T{});
}

}  // namespace

void validateMeshData(const Mesh& mesh, std::string_view source) {
    const std::size_t n = mesh.positions.size();
    if (mesh.indices.empty()) throw InputError(format("{}: contains no triangles", source));
    if (mesh.indices.size() % 3 != 0)
        throw InputError(format("{}: index count {} is not a multiple of 3", source, mesh.indices.size()));
    for (std::size_t i = 0; i < n; ++i) {
        const glm::vec3& p = mesh.positions[i];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            throw InputError(format("{}: vertex {} has a non-finite coordinate ({}, {}, {})", source, i, p.x,
                                         p.y, p.z));
    }
    for (std::size_t i = 0; i < mesh.indices.size(); ++i)
        if (mesh.indices[i] >= n)
            throw InputError(format("{}: triangle {} uses vertex index {} but there are only {} vertices",
                                         source, i / 3, mesh.indices[i], n));
    checkAttributeSize(mesh.normals, n, source, "normals");
    checkAttributeSize(mesh.uv0, n, source, "uv0");
    checkAttributeSize(mesh.uv1, n, source, "uv1");
    checkAttributeSize(mesh.uv2, n, source, "uv2");
    checkAttributeSize(mesh.uv3, n, source, "uv3");
    checkAttributeSize(mesh.materialIds, n, source, "material IDs");
    checkAttributeSize(mesh.pieceIds, n, source, "piece IDs");
    for (std::size_t i = 0; i < mesh.normals.size(); ++i) {
        const glm::vec3& v = mesh.normals[i];
        if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
            throw InputError(format("{}: normal {} is not finite", source, i));
    }
    for (std::size_t i = 0; i < mesh.materialIds.size(); ++i)
        if (mesh.materialIds[i] >= kMaterialIdCount)
            throw InputError(format("{}: vertex {} has material ID {} (IDs are 0 to 15)", source, i,
                                         int(mesh.materialIds[i])));
}

void appendMesh(Mesh& dst, const Mesh& src, const glm::mat4& transform) {
    const std::size_t base = dst.positions.size();
    const std::size_t total = base + src.positions.size();
    // The result has an attribute where either side has it; the other side's part is
    // filled by resizeAttribute. Attributes other than normals are copied as they are.
    resizeAttribute(dst.normals, base, total, !src.normals.empty());
    auto carry = [&](auto& d, const auto& s) {
        resizeAttribute(d, base, total, !s.empty());
        for (std::size_t i = 0; i < s.size(); ++i) d[base + i] = s[i];
    };
    carry(dst.uv0, src.uv0);
    carry(dst.uv1, src.uv1);
    carry(dst.uv2, src.uv2);
    carry(dst.uv3, src.uv3);
    carry(dst.materialIds, src.materialIds);
    carry(dst.pieceIds, src.pieceIds);

    // No reserve(): an exact one per call would copy the whole mesh on every append.
    const glm::mat3 normalMatrix = glm::inverseTranspose(glm::mat3(transform));
    for (const glm::vec3& p : src.positions) dst.positions.push_back(glm::vec3(transform * glm::vec4(p, 1.0f)));
    for (std::size_t i = 0; i < src.normals.size(); ++i) {
        const glm::vec3 n = normalMatrix * src.normals[i];
        const float len = glm::length(n);
        dst.normals[base + i] = len > 0.0f ? n / len : n;
    }
    // A mirroring transform turns the winding inside out: restore counter-clockwise.
    const bool mirrored = glm::determinant(glm::mat3(transform)) < 0.0f;
    for (std::size_t t = 0; t + 2 < src.indices.size(); t += 3) {
        const auto a = static_cast<std::uint32_t>(base + src.indices[t]);
        const auto b = static_cast<std::uint32_t>(base + src.indices[t + 1]);
        const auto c = static_cast<std::uint32_t>(base + src.indices[t + 2]);
        dst.indices.insert(dst.indices.end(), {a, mirrored ? c : b, mirrored ? b : c});
    }
}

void flipOrientation(Mesh& mesh) {
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) std::swap(mesh.indices[t + 1], mesh.indices[t + 2]);
    for (glm::vec3& n : mesh.normals) n = -n;
}

std::vector<std::uint32_t> weldByPosition(std::span<const glm::vec3> positions) {
    struct Hash {
        std::size_t operator()(const glm::vec3& p) const {
            // Hash the bit patterns; +0 and -0 compare equal, so fold them first.
            auto bits = [](float f) {
                f = f == 0.0f ? 0.0f : f;
                std::uint32_t u;
                std::memcpy(&u, &f, sizeof u);
                return std::size_t(u);
            };
            return bits(p.x) * 73856093u ^ bits(p.y) * 19349663u ^ bits(p.z) * 83492791u;
        }
    };
    std::unordered_map<glm::vec3, std::uint32_t, Hash> first;
    first.reserve(positions.size());
    std::vector<std::uint32_t> canonical(positions.size());
    for (std::size_t i = 0; i < positions.size(); ++i)
        canonical[i] = first.try_emplace(positions[i], static_cast<std::uint32_t>(i)).first->second;
    return canonical;
}

}  // namespace dawnforge
