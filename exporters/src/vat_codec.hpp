#pragma once
// What vat.cpp and vat_ldr.cpp share (private to the exporters module): the engine axes of a
// preset, the Labs quaternion packing and its inverse, and the transforms' accessors.
#include <dawnforge/exporters/vat.hpp>

#include <Imath/half.h>
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

// A texel value as the HDR textures store it: rounded to half with --half.
inline float store(double v, bool half) { return half ? float(Imath::half(float(v))) : float(v); }

// Where piece j's texel of frame k starts in an RGBA texture.
inline std::size_t texelOffset(const VatLayout& L, std::size_t j, int k) {
    const std::size_t row = std::size_t(k) * std::size_t(L.rowsPerFrame) + j / std::size_t(L.width);
    return (row * std::size_t(L.width) + j % std::size_t(L.width)) * 4;
}

// The Non-HDR form (vat_ldr.cpp). What its bounds carry: the largest turns per frame (the
// HDA's max RPF: at least 1), the largest piece scale, and whether a second texture holds the
// positions' hundredths.
struct LdrCodes {
    double maxTurns = 1.0, maxScale = 1.0;
    bool twoTextures = true;
};
// The codes for `vat` in its HDR values: the largest piece scale centres the packing cases the
// position alpha holds on a scale of 1 (exact when only case 0 occurs, ± 0.59 % for all four).
LdrCodes ldrCodes(const Vat& vat, bool twoTextures);

// Rewrites vat.position and vat.rotation (the HDR values, engine axes and units) in the
// Non-HDR form as k / 255, fills vat.position2 (with codes.twoTextures), and measures the
// errors of what the Labs decoders read back (vat.max*Error) against the animation. `lo`,
// `hi`: the encoded bounds the engines lerp between (engine axes and units); radius: each
// piece's.
void quantizeLdr(Vat& vat, const VatAnimation& animation, const Engine& engine, const glm::dvec3& lo,
                 const glm::dvec3& hi, const LdrCodes& codes, std::span<const double> radius);

// Fills vat.dust and vat.dustLayout from animation's puffs (vat_dust.cpp); nothing without dust.
void encodeDust(Vat& vat, const VatAnimation& animation, const Engine& engine, const VatSettings& settings);

}  // namespace dawnforge::exporters::vat_codec
