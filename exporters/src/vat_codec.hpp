#pragma once
// What vat.cpp and vat_ldr.cpp share (private to the exporters module): the engine axes of a
// preset, the Labs quaternion packing and its inverse, and the transforms' accessors.
#include <dawnforge/exporters/vat.hpp>

#include <glm/gtc/quaternion.hpp>
#include <glm/mat3x3.hpp>

#include <span>

namespace dawnforge::exporters::vat_codec {

// Engine space = scale × axes × (our / Houdini space: metres, +Y up, right-handed).
struct Engine {
    glm::dmat3 axes{1.0};
    double scale = 1.0;
    double handedness = 1.0;  // det(axes)
    // Applied to the packed triple, an axial vector: a mirror also flips its sign.
    glm::dmat3 tripleMap() const { return handedness * axes; }
    glm::dvec3 toOurs(const glm::dvec3& engine) const { return glm::transpose(axes) * engine / scale; }
};
Engine engineOf(VatPreset preset);

// Labs packing: index m of the largest-magnitude component in (w, x, y, z) order, the
// quaternion negated so it is positive, dropped, and w written in its slot.
struct PackedRotation {
    glm::dvec3 triple{0.0};
    int dropped = 0;
    glm::dquat canonical{1.0, 0.0, 0.0, 0.0};
};
PackedRotation pack(glm::dquat q);
// The inverse of pack() in our axes (the `native` decoder).
glm::dquat unpack(const glm::dvec3& triple, int dropped);
// The angle between two orientations (rad), whatever their signs.
double angleBetween(const glm::dquat& a, const glm::dquat& b);

inline glm::dquat orientation(std::span<const float> transforms, std::size_t index) {
    const float* t = transforms.data() + index * 7;
    return glm::normalize(glm::dquat(t[6], t[3], t[4], t[5]));
}
inline glm::dvec3 position(std::span<const float> transforms, std::size_t index) {
    const float* t = transforms.data() + index * 7;
    return {t[0], t[1], t[2]};
}

// The Non-HDR form (vat_ldr.cpp). `lo`, `hi`: the encoded bounds the engines lerp between
// (engine axes and units); maxTurns: the largest turns per frame the bounds carry (≥ 1);
// maxScale: the largest piece scale they carry (ldrMaxScale).
struct LdrRange {
    glm::dvec3 lo{0.0}, hi{1.0};
    double maxTurns = 1.0;
    double maxScale = 1.0;
    bool twoTextures = true;  // the positions' hundredths in vat.position2
};
// The largest piece scale for the packing cases m in [lo, hi] that the position alpha holds:
// the smallest 8-bit alpha of case m decodes (1 − frac(4a)) × maxScale = (1 − m/255) ×
// maxScale, so this centres the cases used on 1 (1 when only case 0 occurs; ± 0.59 % for all).
inline double ldrMaxScale(int lo, int hi) { return 2.0 / ((1.0 - lo / 255.0) + (1.0 - hi / 255.0)); }

// Rewrites vat.position and vat.rotation (the HDR values, engine axes and units) in the
// Non-HDR form as k / 255, fills vat.position2 (with range.twoTextures), and measures the errors of what the Labs
// decoders read back (vat.max*Error) against the animation. radius: each piece's.
void quantizeLdr(Vat& vat, const VatAnimation& animation, const Engine& engine, const LdrRange& range,
                 std::span<const double> radius);

}  // namespace dawnforge::exporters::vat_codec
