// Dust beside the pieces (vat.hpp): the simulation's puffs (sim.json's debris.dust) in one
// texture of their own, <name>_dust.exr, laid out like the pieces' textures.
//   W = min(maxWidth, puffs), R = ceil(puffs / W) rows per frame; puff p at frame k is the
//   texel at column p mod W, row k·R + floor(p / W) (centre, size) and, in the texture's
//   second half, row (frames + k)·R + floor(p / W) (opacity, 0, 0, 1).
//   Centre RGB in engine axes and units, A the puff's diameter in engine units.
// The runtime draws each puff as a camera-facing soft sprite (runtime/shaders/dust.vert).
#include "vat_codec.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>

#include <algorithm>
#include <cmath>

namespace dawnforge::exporters::vat_codec {

void encodeDust(Vat& vat, const VatAnimation& animation, const Engine& engine, const VatSettings& settings) {
    const std::size_t puffs = animation.dustPuffs;
    if (puffs == 0) return;
    if (animation.dust.size() != std::size_t(animation.frames) * puffs * 5)
        throw InputError(format("the dust holds {} values, but {} frames of {} puffs need {}", animation.dust.size(),
                                animation.frames, puffs, std::size_t(animation.frames) * puffs * 5));
    VatLayout L = vatLayout(puffs, 2 * animation.frames, settings.maxWidth);  // centres, then opacities
    L.frames = animation.frames;
    vat.dustLayout = L;
    vat.dust.assign(std::size_t(L.width) * std::size_t(L.height) * 4, 0.0f);
    const std::size_t half = std::size_t(L.frames) * std::size_t(L.rowsPerFrame) * std::size_t(L.width) * 4;
    for (int k = 0; k < animation.frames; ++k)
        for (std::size_t p = 0; p < puffs; ++p) {
            const float* d = animation.dust.data() + (std::size_t(k) * puffs + p) * 5;
            for (int c = 0; c < 5; ++c)
                if (!std::isfinite(d[c])) throw InputError("the dust contains a value that is not finite");
            const glm::dvec3 centre = engine.scale * (engine.axes * glm::dvec3(d[0], d[1], d[2]));
            float* t = vat.dust.data() + texelOffset(L, p, k);
            t[0] = store(centre.x, settings.half);
            t[1] = store(centre.y, settings.half);
            t[2] = store(centre.z, settings.half);
            t[3] = store(engine.scale * d[3], settings.half);
            float* o = t + half;
            o[0] = store(std::clamp(double(d[4]), 0.0, 1.0), settings.half);
            o[3] = 1.0f;
        }
}

}  // namespace dawnforge::exporters::vat_codec
