#pragma once
// The pieces of a destruction VAT as boxes for the probes' capture (issue 14 item 2: moving
// destruction pieces are captured as boxes too), private to the renderer. Each piece is its
// rest mesh's box about its pivot, coloured by its commonest material, turned and moved as
// vat.vert moves it at the nearest frame.
#include <dawnforge/exporters/vat_read.hpp>
#include <dawnforge/runtime/probe_placement.hpp>

#include <glm/glm.hpp>

#include <vector>

namespace dawnforge::runtime {

class VatPieceBoxes {
public:
    VatPieceBoxes() = default;
    // `model` places the VAT; its frame 0 plays at scene time `startTime` at `fps`.
    VatPieceBoxes(const exporters::VatFile& file, const glm::mat4& model, double startTime);
    // Appends every piece's box at scene time `time` (the first frame before startTime).
    void append(double time, std::vector<ProbeBox>& out) const;
    std::size_t pieces() const { return pieces_.size(); }

private:
    struct Piece {
        glm::vec3 centre{0.0f}, half{0.0f};  // rest box about the pivot
        glm::vec3 colour{0.5f};
        glm::ivec2 texel{0};                 // frame 0's texel
    };
    std::vector<Piece> pieces_;
    std::vector<float> position_, rotation_;
    exporters::VatLayout layout_;
    glm::mat4 model_{1.0f};
    double fps_ = 30.0, startTime_ = 0.0;
};

}  // namespace dawnforge::runtime
