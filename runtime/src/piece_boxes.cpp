// Destruction pieces as capture boxes (piece_boxes.hpp).
#include "piece_boxes.hpp"

#include <dawnforge/core/materials.hpp>

#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace dawnforge::runtime {

namespace {

// vat.vert's unpackRotation: the three stored components and the dropped one's index.
glm::quat unpackRotation(glm::vec3 t, int dropped) {
    const float r = std::sqrt(std::max(0.0f, 1.0f - glm::dot(t, t)));
    switch (dropped) {
        case 0: return {r, t.x, t.y, t.z};  // glm::quat(w, x, y, z)
        case 1: return {t.x, r, t.y, t.z};
        case 2: return {t.y, t.x, r, t.z};
        default: return {t.z, t.x, t.y, r};
    }
}

}  // namespace

VatPieceBoxes::VatPieceBoxes(const exporters::VatFile& file, const glm::mat4& model, double startTime)
    : position_(file.position), rotation_(file.rotation), layout_(file.layout), model_(model), fps_(file.fps),
      startTime_(startTime) {
    const Mesh& m = file.mesh;
    const float inf = std::numeric_limits<float>::infinity();
    std::vector<glm::vec3> lo(layout_.pieces, glm::vec3(inf)), hi(layout_.pieces, glm::vec3(-inf));
    std::vector<std::array<int, 16>> materials(layout_.pieces, std::array<int, 16>{});
    pieces_.assign(layout_.pieces, Piece{});
    for (std::size_t i = 0; i < m.positions.size(); ++i) {
        const std::size_t j = m.pieceIds[i];
        const glm::vec3 pivot(m.uv2.empty() ? 0.0f : m.uv2[i].x, m.uv3.empty() ? 0.0f : m.uv3[i].x, m.uv3.empty() ? 0.0f : m.uv3[i].y);
        lo[j] = glm::min(lo[j], m.positions[i] - pivot);
        hi[j] = glm::max(hi[j], m.positions[i] - pivot);
        ++materials[j][m.materialIds.empty() ? 0 : m.materialIds[i] & 15u];
        pieces_[j].texel = glm::ivec2(int(m.uv1[i].x * float(layout_.width)), int(m.uv1[i].y * float(layout_.height)));
    }
    for (std::size_t j = 0; j < pieces_.size(); ++j) {
        if (lo[j].x > hi[j].x) continue;  // a piece without vertices stays an empty box
        pieces_[j].centre = 0.5f * (lo[j] + hi[j]);
        pieces_[j].half = glm::max(0.5f * (hi[j] - lo[j]), glm::vec3(0.01f));
        const auto commonest = std::max_element(materials[j].begin(), materials[j].end()) - materials[j].begin();
        pieces_[j].colour = materialMeanColour(std::uint8_t(commonest));
    }
}

void VatPieceBoxes::append(double time, std::vector<ProbeBox>& out) const {
    const int frame = std::clamp(int(std::lround((time - startTime_) * fps_)), 0, layout_.frames - 1);
    const glm::mat3 turn(model_);
    for (const Piece& p : pieces_) {
        if (p.half == glm::vec3(0.0f)) continue;
        const std::size_t texel =
            (std::size_t(p.texel.y + frame * layout_.rowsPerFrame) * std::size_t(layout_.width) + std::size_t(p.texel.x)) * 4;
        const glm::vec3 pivot(position_[texel], position_[texel + 1], position_[texel + 2]);
        const glm::quat q = unpackRotation({rotation_[texel], rotation_[texel + 1], rotation_[texel + 2]},
                                           int(std::floor(4.0f * position_[texel + 3] + 0.5f)));
        ProbeBox box;
        box.centre = glm::dvec3(model_ * glm::vec4(pivot + q * p.centre, 1.0f));
        box.u = glm::dvec3(glm::normalize(turn * (q * glm::vec3(1, 0, 0))));
        box.up = glm::dvec3(glm::normalize(turn * (q * glm::vec3(0, 1, 0))));
        box.w = glm::dvec3(glm::normalize(turn * (q * glm::vec3(0, 0, 1))));
        box.halfSize = glm::dvec3(p.half);
        box.colours.fill(p.colour);
        out.push_back(box);
    }
}

}  // namespace dawnforge::runtime
