// The SideFX Labs VAT 3.0 "Non-HDR" rigid-body form (vat_codec.hpp), as the Labs shaders read
// it (the URP_VAT3 rigid-body graph; the Unreal material function's documented behaviour):
//   position = (pos.rgb + 0.01 × pos2.rgb) × (max − min) + min of the encoded bounds;
//   rotation = (rot − 0.5) × 2: the packed triple, and the turns to the next frame over the
//   largest turns per frame (the code on Houdini's max x);
//   position alpha as in HDR: floor(4a) is the dropped component, (1 − frac(4a)) × the largest
//   piece scale (the code on Houdini's max y) the piece's scale.
// Each value is chosen among its 8-bit neighbours for what the decoder reads back, not rounded
// on its own: positions split so that the hundredths hold the remainder, the three rotation
// components together for the smallest angle.
#include "vat_codec.hpp"

#include <algorithm>
#include <cmath>

namespace dawnforge::exporters::vat_codec {

namespace {

float unorm(long k) { return float(k) / 255.0f; }

// n in [0, 1] as a / 255 + 0.01 × b / 255: a the 8-bit floor, b the remainder's hundredths
// (the remainder is below 1/255, which 0.01 × 255/255 covers); or, in one texture, a / 255
// rounded. Returns what a decoder reads.
double splitUnit(double n, bool two, float& upper, float& lower) {
    n = std::clamp(n, 0.0, 1.0);
    if (!two) {
        const long a = std::lround(n * 255.0);
        upper = unorm(a);
        return double(a) / 255.0;
    }
    const long a = std::min(255L, long(std::floor(n * 255.0)));
    const long b = std::clamp(std::lround((n - double(a) / 255.0) * 255.0 * 100.0), 0L, 255L);
    upper = unorm(a);
    lower = unorm(b);
    return double(a) / 255.0 + 0.01 * double(b) / 255.0;
}

// The triple (engine axes) as three bytes (v + 1) / 2, each rounded down or up, whichever of
// the 8 combinations the decoder turns into the orientation nearest `canonical`.
double quantizeTriple(const glm::dvec3& triple, int dropped, const glm::dquat& canonical, const Engine& engine,
                      float* out) {
    glm::dvec3 base;
    for (int c = 0; c < 3; ++c) base[c] = std::floor((triple[c] + 1.0) * 0.5 * 255.0);
    double best = 1e9;
    for (int combination = 0; combination < 8; ++combination) {
        glm::dvec3 bytes;
        for (int c = 0; c < 3; ++c) bytes[c] = std::clamp(base[c] + double((combination >> c) & 1), 0.0, 255.0);
        const glm::dvec3 decoded = bytes / 255.0 * 2.0 - 1.0;
        const double error = angleBetween(unpack(glm::transpose(engine.tripleMap()) * decoded, dropped), canonical);
        if (error < best) {
            best = error;
            for (int c = 0; c < 3; ++c) out[c] = unorm(long(bytes[c]));
        }
    }
    return best;
}

// The turns over maxTurns as (a + 1) / 2 in a byte, on the side of 0.5 that keeps its sign (0
// has no byte: 128, just above): a flipped sign would slerp the other way round.
float quantizeTurns(double turns, double maxTurns) {
    const long k = std::clamp(std::lround((turns / maxTurns + 1.0) * 0.5 * 255.0), 0L, 255L);
    return unorm(turns >= 0.0 ? std::max(k, 128L) : std::min(k, 127L));
}

// The dropped component m as the smallest byte with floor(4a) = m; returns the scale the
// decoder reads: (1 − frac(4a)) × maxScale.
double quantizeCase(int dropped, double maxScale, float& out) {
    const long k = long(std::ceil(255.0 * dropped / 4.0));
    out = unorm(k);
    const double four = 4.0 * double(k) / 255.0;
    return (1.0 - (four - std::floor(four))) * maxScale;
}

}  // namespace

LdrCodes ldrCodes(const Vat& vat, bool twoTextures) {
    int lo = 3, hi = 0;
    for (std::size_t i = 3; i < vat.position.size(); i += 4) {
        const int m = int(std::lround(4.0 * vat.position[i]));
        lo = std::min(lo, m), hi = std::max(hi, m);
    }
    // The smallest alpha of case m decodes (1 − m/255) × maxScale: centre the cases used on 1.
    const double maxScale = 2.0 / ((1.0 - lo / 255.0) + (1.0 - hi / 255.0));
    return {std::max(1.0, vat.maxTurnsPerFrame), maxScale, twoTextures};
}

void quantizeLdr(Vat& vat, const VatAnimation& animation, const Engine& engine, const glm::dvec3& lo,
                 const glm::dvec3& hi, const LdrCodes& codes, std::span<const double> radius) {
    const VatLayout& L = vat.layout;
    const std::size_t n = L.pieces;
    std::vector<float> hundredths(vat.position.size(), 1.0f);
    vat.maxPositionError = vat.maxRotationError = vat.maxVertexError = vat.maxScaleError = 0.0;
    const glm::dvec3 extent = hi - lo;
    for (std::size_t j = 0; j < n; ++j) {
        const glm::dquat rest = orientation(animation.transforms, j);
        for (int k = 0; k < L.frames; ++k) {
            const std::size_t index = std::size_t(k) * n + j, texel = texelOffset(L, j, k);
            float* pos = vat.position.data() + texel;
            float* pos2 = hundredths.data() + texel;
            float* rot = vat.rotation.data() + texel;
            const glm::dvec3 P = position(animation.transforms, index);
            const glm::dvec3 pe = engine.scale * (engine.axes * P);
            glm::dvec3 decoded;
            for (int c = 0; c < 3; ++c)
                decoded[c] = lo[c] + splitUnit((pe[c] - lo[c]) / extent[c], codes.twoTextures, pos[c], pos2[c]) * extent[c];
            const PackedRotation packed = pack(orientation(animation.transforms, index) * glm::conjugate(rest));
            const double rotationError =
                quantizeTriple(engine.tripleMap() * packed.triple, packed.dropped, packed.canonical, engine, rot);
            rot[3] = quantizeTurns(double(rot[3]), codes.maxTurns);
            const double scaleError = std::abs(quantizeCase(packed.dropped, codes.maxScale, pos[3]) - 1.0);
            const double positionError = glm::length(engine.toOurs(decoded) - P);
            vat.maxPositionError = std::max(vat.maxPositionError, positionError);
            vat.maxRotationError = std::max(vat.maxRotationError, rotationError);
            vat.maxScaleError = std::max(vat.maxScaleError, scaleError);
            vat.maxVertexError = std::max(vat.maxVertexError, positionError + (2.0 * std::sin(0.5 * rotationError) +
                                                                                scaleError) * radius[j]);
        }
    }
    if (codes.twoTextures) vat.position2 = std::move(hundredths);
}

}  // namespace dawnforge::exporters::vat_codec
