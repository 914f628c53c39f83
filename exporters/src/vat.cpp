// VAT 3.0 rigid-body textures (written by exr.cpp). Layout and packing as
// in vat.hpp; read against the public SideFX Labs sources (sideeffects/SideFXLabs: the
// URP_VAT3 shader graphs, the HDA's presets) and shared/notes/vat3-rigid.md.
#include <dawnforge/exporters/vat.hpp>

#include "vat_codec.hpp"

#include <dawnforge/core/atomic_file.hpp>
#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/scene.hpp>
#include <dawnforge/exporters/gltf.hpp>
#include <dawnforge/exporters/image.hpp>

#include <Imath/half.h>
#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <cstring>
#include <sstream>

namespace dawnforge::exporters {

namespace {

using vat_codec::Engine;
using vat_codec::LdrCodes;
using vat_codec::texelOffset;
using vat_codec::engineOf;
using vat_codec::pack;
using vat_codec::unpack;
using vat_codec::orientation;
using vat_codec::PackedRotation;
using vat_codec::position;
using vat_codec::store;

constexpr double kPi = 3.14159265358979323846;
// The most rows per frame whose hundreds the Labs bound code can count (the HDA's own limit).
constexpr int kLabsMaxRowsPerFrame = 1980;


nlohmann::ordered_json vec(const glm::dvec3& v) { return {v.x, v.y, v.z}; }

// A bound snapped outward to the 0.1 (× engine scale) grid that the Labs shaders expect.
double snapDown(double v, double s) { return std::floor(v / (0.1 * s) - 1e-9) * 0.1 * s; }
double snapUp(double v, double s) { return std::ceil(v / (0.1 * s) + 1e-9) * 0.1 * s; }

void checkAnimation(const VatAnimation& animation, std::size_t n) {
    if (!(animation.fps > 0.0)) throw InputError(format("fps must be positive (got {})", animation.fps));
    if (animation.transforms.size() != std::size_t(animation.frames) * n * 7)
        throw InputError(format("the transforms hold {} values, but {} frames of {} pieces need {}",
                                animation.transforms.size(), animation.frames, n, std::size_t(animation.frames) * n * 7));
    for (float v : animation.transforms)
        if (!std::isfinite(v)) throw InputError("the transforms contain a value that is not finite");
    if (!animation.turns.empty() && animation.turns.size() != std::size_t(animation.frames) * n)
        throw InputError(format("the turns hold {} values, but {} frames of {} pieces need {}", animation.turns.size(),
                                animation.frames, n, std::size_t(animation.frames) * n));
    for (float v : animation.turns)
        if (!std::isfinite(v)) throw InputError("the turns contain a value that is not finite");
}

// Each piece's farthest vertex from its pivot (m).
std::vector<double> pieceRadii(std::span<const Mesh> pieces) {
    std::vector<double> radius(pieces.size(), 0.0);
    for (std::size_t j = 0; j < pieces.size(); ++j)
        for (const glm::vec3& p : pieces[j].positions) radius[j] = std::max(radius[j], double(glm::length(p)));
    return radius;
}


// The turns from q to nextQ that the rotation alpha carries: the simulated path's when
// given (`index` into them), else the shortest way. Below a microradian, zero.
double turnsToNext(const glm::dquat& q, const PackedRotation& packed, const glm::dquat& nextQ,
                   const PackedRotation& next, std::span<const float> pathTurns, std::size_t index) {
    double turns = 0.0;
    if (!pathTurns.empty()) {
        // The path runs from q(k) to ±q(k+1) as written; packing may have negated
        // either end, which flips the sign the shader needs.
        const double flip = (glm::dot(packed.canonical, q) < 0.0) != (glm::dot(next.canonical, nextQ) < 0.0) ? -1.0 : 1.0;
        turns = flip * double(pathTurns[index]);
        // The path decides the way round (towards ±q(k+1)) and the whole turns; the stored
        // poses the rest. The Labs slerp takes the alpha as the angle between its two ends, so
        // when the axis turned within the frame (the path's angle is then not the poses'),
        // this keeps it on the great circle between them (seen in a browser: 1.3 mm off at
        // mid-frame on a 7 cm piece whose path and poses differed by 0.02 rad).
        const double way = turns < 0.0 ? -1.0 : 1.0;
        const double poses = std::acos(std::clamp(way * glm::dot(packed.canonical, next.canonical), -1.0, 1.0)) / kPi;
        const double exact = poses + std::max(0.0, std::round(std::abs(turns) - poses));
        if (turns != 0.0 && std::abs(exact - std::abs(turns)) < 0.25) turns = way * exact;
    } else {
        const double d = glm::dot(packed.canonical, next.canonical);
        turns = (d < 0.0 ? -1.0 : 1.0) * std::acos(std::min(1.0, std::abs(d))) / kPi;
    }
    if (std::abs(turns) < 1e-6 / (2.0 * kPi)) turns = 0.0;
    return turns;
}

// Decodes a stored texel pair as the native shader does (back in our axes) and keeps
// the worst error the precision cost.
void measureError(Vat& vat, const Engine& engine, const float* pos, const float* rot, const glm::dvec3& P,
                  const glm::dquat& canonical, double radius) {
    const glm::dvec3 storedP(pos[0], pos[1], pos[2]);
    const glm::dvec3 decodedP = glm::transpose(engine.axes) * storedP / engine.scale;
    const glm::dvec3 storedT(rot[0], rot[1], rot[2]);
    const glm::dquat decodedQ = glm::normalize(unpack(glm::transpose(engine.tripleMap()) * storedT, int(std::floor(4.0 * pos[3]))));
    const double positionError = glm::length(decodedP - P);
    const double rotationError = 2.0 * std::acos(std::min(1.0, std::abs(glm::dot(decodedQ, canonical))));
    vat.maxPositionError = std::max(vat.maxPositionError, positionError);
    vat.maxRotationError = std::max(vat.maxRotationError, rotationError);
    vat.maxVertexError = std::max(vat.maxVertexError, positionError + 2.0 * std::sin(0.5 * rotationError) * radius);
}

// Piece j's texels, frame by frame: each orientation (relative to the rest pose) is
// packed once and carried on as the next frame's start. Grows the bounds by the piece.
void encodePiece(Vat& vat, const VatAnimation& animation, const Engine& engine, bool half, std::size_t j,
                 double radius) {
    const VatLayout& L = vat.layout;
    const std::size_t n = L.pieces;
    const glm::dquat rest = orientation(animation.transforms, j);
    const auto relative = [&](int k) { return orientation(animation.transforms, std::size_t(k) * n + j) * glm::conjugate(rest); };
    glm::dquat q = relative(0);
    PackedRotation packed = pack(q);
    for (int k = 0; k < L.frames; ++k) {
        const std::size_t index = std::size_t(k) * n + j;
        const glm::dvec3 P = position(animation.transforms, index);
        glm::dquat nextQ = q;
        PackedRotation next = packed;
        double turns = 0.0;
        if (k + 1 < L.frames) {
            nextQ = relative(k + 1);
            next = pack(nextQ);
            turns = turnsToNext(q, packed, nextQ, next, animation.turns, index);
            vat.maxTurnsPerFrame = std::max(vat.maxTurnsPerFrame, std::abs(turns));
        }
        const glm::dvec3 pe = engine.scale * (engine.axes * P);
        const glm::dvec3 te = engine.tripleMap() * packed.triple;
        const std::size_t texel = texelOffset(L, j, k);
        float* pos = vat.position.data() + texel;
        float* rot = vat.rotation.data() + texel;
        for (int c = 0; c < 3; ++c) {
            pos[c] = store(pe[c], half);
            rot[c] = store(te[c], half);
        }
        pos[3] = store(0.25 * packed.dropped, half);
        rot[3] = store(turns, half);
        measureError(vat, engine, pos, rot, P, packed.canonical, radius);
        vat.boundsMin = glm::min(vat.boundsMin, pe - glm::dvec3(engine.scale * radius));
        vat.boundsMax = glm::max(vat.boundsMax, pe + glm::dvec3(engine.scale * radius));
        q = nextQ;
        packed = next;
    }
}

// The 13 bits of x at `shift` as a half float whose exponent bits 13-14 are `pattern`, the
// Labs HDA's packing ("Very High" pivots): 0x4000 puts the value in [2, 512), 0x2000 in
// [2^-7, 2), so that the decoder tells the forms apart.
float splitHalf(std::uint32_t bits, int shift, std::uint16_t pattern) {
    const std::uint32_t x = (bits >> shift) & 0x1FFFu;
    Imath::half h;
    h.setBits(std::uint16_t(((x >> 12) << 15) | pattern | ((x & 0xFFFu) << 1)));
    return float(h);
}

float roundToHalf(double v) { return float(Imath::half(float(v))); }

// Unreal's "Very High" pivot (Labs HDA, the Unreal preset): Houdini axes, metres, in
// TEXCOORD_2 and TEXCOORD_3 as Unreal sees them (glTF V, from the top). Either the pivot's x
// and z as halves with y's top 26 bits split over the two V's ("original"), or its direction's
// x and z as halves with its length split ("normalized"), whichever lands nearer.
std::pair<glm::vec2, glm::vec2> veryHighPivot(const glm::dvec3& p) {
    double m = glm::length(p);
    glm::dvec3 n = m > 0.0 ? p / m : glm::dvec3(0, 1, 0);
    if (n.y < 0.0) n = -n, m = -m;
    std::uint32_t mBits = 0, yBits = 0;
    const float mf = float(m), yf = float(p.y);
    std::memcpy(&mBits, &mf, 4);
    std::memcpy(&yBits, &yf, 4);
    mBits &= 0xFFFFFFC0u;
    float mTruncated = 0.0f;
    std::memcpy(&mTruncated, &mBits, 4);
    const double nx = roundToHalf(n.x), nz = roundToHalf(n.z);
    const glm::dvec3 normalized = glm::dvec3(nx, std::sqrt(std::max(0.0, 1.0 - nx * nx - nz * nz)), nz) * double(mTruncated);
    const glm::dvec3 original(roundToHalf(p.x), p.y, roundToHalf(p.z));
    if (glm::distance(p, original) <= glm::distance(p, normalized) || n.y * n.y < 0.001)
        return {{roundToHalf(p.x), splitHalf(yBits, 19, 0x4000)}, {roundToHalf(p.z), splitHalf(yBits, 6, 0x2000)}};
    return {{float(nx), splitHalf(mBits, 19, 0x4000)}, {float(nz), splitHalf(mBits, 6, 0x4000)}};
}

// The pivot UVs (TEXCOORD_2, TEXCOORD_3) for a pivot in our (Houdini) axes and metres: the
// unencoded Labs form (uv3 = (px, 1), uv4 = (py, 1 - pz) with V flipped), or Unreal's Very
// High form (its material takes both in metres and scales by 100 itself).
std::pair<glm::vec2, glm::vec2> pivotUvs(const glm::dvec3& p, bool veryHigh) {
    if (veryHigh) return veryHighPivot(p);
    return {{float(p.x), 0.0f}, {float(p.y), float(p.z)}};
}

bool usesVeryHighPivots(const VatSettings& settings) {
    return settings.preset == VatPreset::Unreal && !settings.fullPrecisionUvs;
}

// The pivot the Unreal material decodes from Very High UVs (Houdini axes, metres).
glm::dvec3 decodeVeryHigh(const glm::vec2& a, const glm::vec2& b) {
    const auto join = [](float hi, float lo) {  // the material's "Decode Magnitude"
        const std::uint32_t h = Imath::half(hi).bits(), l = Imath::half(lo).bits();
        const std::uint32_t bits = ((((h & 0x8000u) | ((h << 2) & 0x7FF8u))) << 16) | (((l & 0x8000u) | ((l << 2) & 0x7FF8u)) << 3);
        float f = 0.0f;
        std::memcpy(&f, &bits, 4);
        return double(f);
    };
    if (std::abs(b.y) < 2.0f) return {a.x, join(a.y, b.y), b.x};
    return glm::dvec3(a.x, std::sqrt(std::max(0.0, 1.0 - double(a.x) * a.x - double(b.x) * b.x)), b.x) * join(a.y, b.y);
}

// The mesh at frame 0, each piece with its lookup texel (TEXCOORD_1) and pivot
// (TEXCOORD_2/3). Returns how far the Very High UVs moved the farthest-moved pivot (m; 0
// for the unencoded form).
double appendPieceMeshes(Mesh& out, const VatAnimation& animation, const VatLayout& L, bool veryHigh) {
    double pivotError = 0.0;
    for (std::size_t j = 0; j < animation.pieces.size(); ++j) {
        Mesh piece = animation.pieces[j];
        const glm::dquat rest = orientation(animation.transforms, j);
        const glm::dvec3 pivot = position(animation.transforms, j);
        const std::size_t count = piece.positions.size();
        for (glm::vec3& p : piece.positions) p = glm::vec3(rest * glm::dvec3(p) + pivot);
        for (glm::vec3& v : piece.normals) v = glm::vec3(rest * glm::dvec3(v));
        const glm::vec2 lookup(float((double(j % std::size_t(L.width)) + 0.5) / L.width),
                               float((double(j / std::size_t(L.width)) + 0.5) / L.height));
        const auto [uv2, uv3] = pivotUvs(pivot, veryHigh);
        if (veryHigh) pivotError = std::max(pivotError, glm::distance(decodeVeryHigh(uv2, uv3), pivot));
        piece.uv1.assign(count, lookup);
        piece.uv2.assign(count, uv2);
        piece.uv3.assign(count, uv3);
        piece.pieceIds.assign(count, std::uint32_t(j));
        appendMesh(out, piece, glm::mat4(1.0f));
    }
    return pivotError;
}

// The bounds on the 0.1 grid the Labs shaders expect, and with the Labs codes for the
// rows per frame added (the encoded bounds the engine presets carry).
struct EngineBounds {
    glm::dvec3 lo{0.0}, hi{0.0};
    glm::dvec3 encodedLo{0.0}, encodedHi{0.0};
};

// Houdini's (our) axes' offset `code` added to the bounds where the engine's axes put it: an
// offset that points along an engine axis raises its max, one against it lowers its min.
void addCode(EngineBounds& b, const Engine& engine, const glm::dvec3& code) {
    const glm::dvec3 e = engine.axes * code;
    for (int a = 0; a < 3; ++a) (e[a] > 0.0 ? b.encodedHi : b.encodedLo)[a] += e[a];
}

EngineBounds engineBounds(const Vat& vat, const Engine& engine, VatFormat format, const LdrCodes& ldr) {
    EngineBounds b;
    const double s = engine.scale;
    for (int a = 0; a < 3; ++a) {
        b.lo[a] = snapDown(vat.boundsMin[a], s);
        b.hi[a] = snapUp(vat.boundsMax[a], s);
    }
    b.encodedLo = b.lo;
    b.encodedHi = b.hi;
    // The codes, in tenths of the 0.1 (× engine scale) cell, on Houdini's axes as the Labs HDA
    // writes them and its materials read them. Max z: 0.5 for HDR, 0.25 for two position
    // textures (Non-HDR only here), and hundreds of rows in hundredths stepping away from the
    // nearest multiple of 0.25 (upwards from 0 or 0.5, downwards to 0.5 or 1.0), skipping
    // the tenths. Min y: rows mod 100 in thousandths.
    const bool hdr = format == VatFormat::Hdr;
    const int R = vat.layout.rowsPerFrame, hundreds = R / 100;
    const double base = hdr ? 0.5 : ldr.twoTextures ? 0.25 : 0.0, steps = 0.01 * double(hundreds + (hundreds > 9) + (hundreds > 18));
    const bool upwards = int(std::floor(base / 0.25)) % 2 == 0;
    const double code = hundreds == 0 ? base : upwards ? base + steps : base + 0.25 - steps;
    addCode(b, engine, glm::dvec3(0.0, -double(R % 100) * 0.001 * s, 0.0));
    addCode(b, engine, glm::dvec3(0.0, 0.0, code * 0.1 * s));
    if (!hdr) {  // max x: the largest turns per frame; max y: the largest piece scale
        addCode(b, engine, glm::dvec3((1.0 - 1.0 / ldr.maxTurns) * 0.1 * s, 0.0, 0.0));
        addCode(b, engine, glm::dvec3(0.0, (1.0 - 1.0 / ldr.maxScale) * 0.1 * s, 0.0));
    }
    return b;
}

// The two data triangles that carry the encoded bounds in an engine preset's mesh, one at
// each corner with 1 cm legs pointing inwards (as the Labs HDA makes them: an importer that
// drops degenerate triangles, as Unreal's does by default, keeps them): lookup UV (0, 0)
// (V flipped), piece id = pieces.
// A corner (glTF axes, metres) in float, rounded away from the bounds' inside as the engine
// sees them (its axes may mirror ours): the Labs Unreal material reads the active area from
// ceil(min) − min in decimetres, which a min on a whole decimetre that float rounded up by a
// hair (−32.1 m is −32.0999985 m) turns from 0 into 1, and then no frame plays.
glm::vec3 outwardFloat(const glm::dvec3& p, double inward, const glm::dmat3& axes) {
    glm::vec3 f(p);
    for (int a = 0; a < 3; ++a) {
        const double in = inward * (axes[a][0] + axes[a][1] + axes[a][2]);  // along engine's axis: + for the min
        if ((double(f[a]) - p[a]) * in > 0.0)
            f[a] = std::nextafter(f[a], in > 0.0 ? -std::numeric_limits<float>::infinity() : std::numeric_limits<float>::infinity());
    }
    return f;
}

void appendDataTriangles(Mesh& out, const EngineBounds& bounds, const Engine& engine, std::size_t pieces) {
    Mesh data;
    for (const auto& [corner, inward] : {std::pair{bounds.encodedHi, -1.0}, std::pair{bounds.encodedLo, 1.0}}) {
        const glm::dvec3 p = glm::transpose(engine.axes) * corner / engine.scale;  // back to glTF axes, metres
        const std::uint32_t base = std::uint32_t(data.positions.size());
        data.positions.push_back(outwardFloat(p, inward, engine.axes));
        for (const glm::dvec3& leg : {glm::dvec3(0, 0.01, 0), glm::dvec3(0, 0, 0.01)})
            data.positions.push_back(glm::vec3(p + inward * leg));
        data.indices.insert(data.indices.end(), {base, base + 1, base + 2});
    }
    const std::size_t m = data.positions.size();
    data.normals.assign(m, glm::vec3(0, 1, 0));
    data.uv0.assign(m, glm::vec2(0));
    data.uv1.assign(m, glm::vec2(0, 1));
    data.uv2.assign(m, glm::vec2(0));
    data.uv3.assign(m, glm::vec2(0));
    data.materialIds.assign(m, 0);
    data.pieceIds.assign(m, std::uint32_t(pieces));
    appendMesh(out, data, glm::mat4(1.0f));
}

// The file names and import settings in _data.json.
nlohmann::ordered_json textureJson(const VatSettings& settings) {
    if (settings.format == VatFormat::Ldr) {
        const bool two = !settings.singlePositionTexture;
        nlohmann::ordered_json t = {{"position", settings.name + "_pos.png"}};
        if (two) t["position2"] = settings.name + "_pos2.png";
        t["rotation"] = settings.name + "_rot.png";
        t["channels"] = "RGBA";
        t["type"] = "8-bit unsigned normalised";
        t["compression"] = "PNG (lossless)";
        t["import"] = std::string("nearest filtering, no mips, sRGB off, alpha not transparency, no compression (Unity "
                                  "RGBA32, Unreal VectorDisplacementmap), no NPOT scaling; ") +
                      (two ? "turn on" : "leave off") + " 'Positions Require Two Textures'";
        return t;
    }
    return {{"position", settings.name + "_pos.exr"},
            {"rotation", settings.name + "_rot.exr"},
            {"channels", "RGBA"},
            {"type", settings.half ? "half" : "float"},
            {"compression", "PIZ"},
            {"import", "nearest filtering, no mips, sRGB off, no compression or HDR compression, no NPOT scaling"}};
}

// The dust's texture (vat_dust.cpp), or why there is none.
nlohmann::ordered_json dustJson(const Vat& vat, const VatAnimation& animation, const VatSettings& settings) {
    nlohmann::ordered_json j = {{"puffs", animation.dustPuffs}};
    if (vat.dust.empty()) {
        j["file"] = nullptr;
        if (animation.dustPuffs > 0) j["note"] = "the ldr format does not carry dust (an 8-bit texture of puffs is not written)";
        return j;
    }
    const VatLayout& L = vat.dustLayout;
    j["file"] = settings.name + "_dust.exr";
    j["W"] = L.width;
    j["R"] = L.rowsPerFrame;
    j["height"] = L.height;
    j["layout"] = "puff p at frame k: column p mod W, row k·R + floor(p / W): centre RGB (engine axes and units), A its "
                  "diameter; row (frames + k)·R + floor(p / W): opacity in R, A = 1. Row 0 at the top";
    j["draw"] = "a camera-facing sprite per puff, soft (faded where it meets the scene's depth), lit by the sun and the sky";
    return j;
}

// <name>_data.json: the layout, conventions and measured errors an importer needs.
std::string dataJson(const Vat& vat, const VatAnimation& animation, const VatSettings& settings,
                     const EngineBounds& bounds, const LdrCodes& codes) {
    const VatLayout& L = vat.layout;
    const bool ldr = settings.format == VatFormat::Ldr;
    nlohmann::ordered_json j;
    j["format"] = "dawnforge.vat";
    j["version"] = 1;
    j["name"] = settings.name;
    j["preset"] = std::string(vatPresetName(settings.preset));
    j["mode"] = "rigid-body dynamics (SideFX Labs VAT 3.0 layout)";
    j["frames"] = L.frames;
    j["fps"] = animation.fps;
    j["pieces"] = L.pieces;
    j["W"] = L.width;
    j["R"] = L.rowsPerFrame;
    j["height"] = L.height;
    j["texture_format"] = std::string(vatFormatName(settings.format));
    j["precision"] = ldr ? "8-bit" : settings.half ? "half" : "float32";
    j["units"] = settings.preset == VatPreset::Unreal ? "centimetres" : "metres";
    j["axes"] = settings.preset == VatPreset::Native  ? "+Y up, right-handed (glTF)"
                : settings.preset == VatPreset::Unity ? "Unity: x mirrored (-x, y, z)"
                                                       : "Unreal: (x, z, y), Z up";
    j["bounds"] = {{"min", vec(vat.boundsMin)}, {"max", vec(vat.boundsMax)}};
    j["encoded_bounds"] = {{"min", vec(bounds.encodedLo)}, {"max", vec(bounds.encodedHi)}};
    j["max_turns_per_frame"] = vat.maxTurnsPerFrame;
    j["max_position_error"] = vat.maxPositionError;
    j["max_rotation_error"] = vat.maxRotationError;
    j["max_pivot_error"] = vat.maxPivotError;
    j["max_vertex_error"] = vat.maxVertexError;
    if (ldr) {
        j["max_scale_error"] = vat.maxScaleError;
        j["ldr"] = {{"max_turns_per_frame", codes.maxTurns},
                    {"max_piece_scale", codes.maxScale},
                    {"position", std::string(codes.twoTextures ? "(pos.rgb + 0.01 × pos2.rgb)" : "pos.rgb") +
                                     " × (encoded max − encoded min) + encoded min"},
                    {"rotation", "(rot.rgb − 0.5) × 2; turns = (rot.a − 0.5) × 2 × max_turns_per_frame"},
                    {"position_alpha", "floor(4a): the dropped component; (1 − frac(4a)) × max_piece_scale: the piece's scale"}};
    }
    j["textures"] = textureJson(settings);
    j["dust"] = dustJson(vat, animation, settings);
    j["mesh"] = {{"file", settings.name + "_mesh.glb"},
                 {"lookup_uv", "TEXCOORD_1: texel centre of frame 0 (glTF V, from the top)"},
                 {"pivot", usesVeryHighPivots(settings)
                               ? "TEXCOORD_2, TEXCOORD_3: the Labs 'Very High' form (Houdini axes, metres; halves with a "
                                 "26-bit y or length split over the two V's), for Unreal's default 16-bit UVs"
                               : std::string("TEXCOORD_2 = (px, 0), TEXCOORD_3 = (py, pz): Houdini axes, metres (Labs uv3 = "
                                             "(px, 1), uv4 = (py, 1 - pz) with V flipped)") +
                                     (settings.preset == VatPreset::Unreal ? "; turn on 'Use Full Precision UVs' in Unreal" : "")},
                 {"data_triangles", settings.preset != VatPreset::Native ? 2 : 0}};
    if (settings.preset == VatPreset::Unity) {
        // The Labs Unity material reads these properties (not the mesh bounds): the encoded
        // bounds in Unity axes, as the HDA writes them into the .mat.
        const glm::dvec3& lo = bounds.encodedLo;
        const glm::dvec3& hi = bounds.encodedHi;
        j["unity_material"] = {{"_B_autoPlayback", 1}, {"_frameCount", L.frames}, {"_playbackSpeed", 1.0},
                               {"_houdiniFPS", animation.fps},   {"_B_interpolate", 1},
                               {"_B_pscaleAreInPosA", 1},        {"_B_LOAD_POS_TWO_TEX", ldr && codes.twoTextures ? 1 : 0},
                               {"_boundMinX", lo.x},             {"_boundMinY", lo.y},
                               {"_boundMinZ", lo.z},             {"_boundMaxX", hi.x},
                               {"_boundMaxY", hi.y},             {"_boundMaxZ", hi.z}};
    }
    return j.dump(1) + "\n";
}

}  // namespace

std::optional<VatPreset> parseVatPreset(std::string_view name) {
    if (name == "native") return VatPreset::Native;
    if (name == "unreal") return VatPreset::Unreal;
    if (name == "unity") return VatPreset::Unity;
    return std::nullopt;
}

std::optional<VatFormat> parseVatFormat(std::string_view name) {
    if (name == "hdr") return VatFormat::Hdr;
    if (name == "ldr") return VatFormat::Ldr;
    return std::nullopt;
}

std::string_view vatFormatName(VatFormat format) { return format == VatFormat::Ldr ? "ldr" : "hdr"; }

std::string_view vatPresetName(VatPreset preset) {
    switch (preset) {
        case VatPreset::Native: return "native";
        case VatPreset::Unreal: return "unreal";
        case VatPreset::Unity: return "unity";
    }
    return "native";
}

VatLayout vatLayout(std::size_t pieces, int frames, int maxWidth) {
    if (maxWidth < 1 || maxWidth > kVatMaxTextureSize)
        throw InputError(format("the maximum width must be between 1 and {} (got {})", kVatMaxTextureSize, maxWidth));
    if (pieces == 0) throw InputError("there are no pieces to bake");
    if (frames < 1) throw InputError(format("there must be at least one frame (got {})", frames));
    VatLayout l;
    l.pieces = pieces;
    l.frames = frames;
    l.width = int(std::min<std::size_t>(std::size_t(maxWidth), pieces));
    const std::size_t rows = (pieces + std::size_t(l.width) - 1) / std::size_t(l.width);
    if (rows > std::size_t(kVatMaxTextureSize))
        throw InputError(format("{} pieces need {} rows per frame at width {}: more than the {} a texture can have",
                                pieces, rows, l.width, kVatMaxTextureSize));
    l.rowsPerFrame = int(rows);
    const std::size_t height = rows * std::size_t(frames);
    if (height > std::size_t(kVatMaxTextureSize))
        throw InputError(format("{} frames × {} rows per frame = {} rows, more than {}; at most {} frames fit "
                                "(fewer frames, or a larger maximum width if it is below {})",
                                frames, rows, height, kVatMaxTextureSize, kVatMaxTextureSize / rows, kVatMaxTextureSize));
    l.height = int(height);
    return l;
}

Vat encodeVat(const VatAnimation& animation, const VatSettings& settings) {
    const std::size_t n = animation.pieces.size();
    Vat vat;
    vat.layout = vatLayout(n, animation.frames, settings.maxWidth);
    checkAnimation(animation, n);
    if (settings.fullPrecisionUvs && settings.preset != VatPreset::Unreal)
        throw InputError(format("--full-precision-uvs is for the unreal preset (the {} preset's pivots are exact already)",
                                vatPresetName(settings.preset)));
    const bool ldr = settings.format == VatFormat::Ldr;
    if (ldr && settings.half) throw InputError("--half is for the hdr format (ldr textures are 8-bit)");
    if (!ldr && settings.singlePositionTexture)
        throw InputError("--single-position-texture is for the ldr format (hdr positions are in one texture)");
    if (ldr && settings.preset == VatPreset::Native)
        throw InputError("the ldr format is for the unity and unreal presets (the Labs shaders); the native preset is what "
                         "the dawnforge runtime plays, in hdr");
    if (settings.preset != VatPreset::Native && vat.layout.rowsPerFrame > kLabsMaxRowsPerFrame)
        throw InputError(format("{} rows per frame: the Labs bounds carry at most {} (a larger --max-width)",
                                vat.layout.rowsPerFrame, kLabsMaxRowsPerFrame));
    const Engine engine = engineOf(settings.preset);
    const std::size_t texels = std::size_t(vat.layout.width) * std::size_t(vat.layout.height);
    vat.position.assign(texels * 4, 0.0f);
    vat.rotation.assign(texels * 4, 0.0f);
    vat.boundsMin = glm::dvec3(std::numeric_limits<double>::max());
    vat.boundsMax = glm::dvec3(-std::numeric_limits<double>::max());
    const std::vector<double> radius = pieceRadii(animation.pieces);
    for (std::size_t j = 0; j < n; ++j) encodePiece(vat, animation, engine, settings.half, j, radius[j]);

    const LdrCodes codes = ldr ? vat_codec::ldrCodes(vat, !settings.singlePositionTexture) : LdrCodes{};
    const EngineBounds bounds = engineBounds(vat, engine, settings.format, codes);
    if (ldr)
        vat_codec::quantizeLdr(vat, animation, engine, bounds.encodedLo, bounds.encodedHi, codes, radius);

    // A pivot the UVs carry a little off moves every vertex of its piece by as much.
    vat.maxPivotError = appendPieceMeshes(vat.mesh, animation, vat.layout, usesVeryHighPivots(settings));
    vat.maxVertexError += vat.maxPivotError;
    vat.mesh.name = settings.name;
    if (settings.preset != VatPreset::Native) appendDataTriangles(vat.mesh, bounds, engine, n);
    if (!ldr) vat_codec::encodeDust(vat, animation, engine, settings);
    vat.dataJson = dataJson(vat, animation, settings, bounds, codes);
    return vat;
}

namespace {

Image ldrImage(std::span<const float> unorm, const VatLayout& layout) {
    Image image;
    image.width = layout.width;
    image.height = layout.height;
    image.rgba.resize(unorm.size());
    for (std::size_t i = 0; i < unorm.size(); ++i)
        image.rgba[i] = std::uint8_t(std::clamp(std::lround(double(unorm[i]) * 255.0), 0L, 255L));
    return image;
}

}  // namespace

void writeVat(const Vat& vat, const VatSettings& settings, const std::filesystem::path& dir) {
    ensureOutputDirectory(dir);
    std::vector<std::pair<std::string, std::vector<std::byte>>> textures;
    if (settings.format == VatFormat::Ldr) {
        textures.emplace_back("_pos.png", encodePng(ldrImage(vat.position, vat.layout)));
        if (!vat.position2.empty()) textures.emplace_back("_pos2.png", encodePng(ldrImage(vat.position2, vat.layout)));
        textures.emplace_back("_rot.png", encodePng(ldrImage(vat.rotation, vat.layout)));
    } else {
        textures.emplace_back("_pos.exr", encodeExr(vat.position, vat.layout.width, vat.layout.height, settings.half));
        textures.emplace_back("_rot.exr", encodeExr(vat.rotation, vat.layout.width, vat.layout.height, settings.half));
        if (!vat.dust.empty())
            textures.emplace_back("_dust.exr", encodeExr(vat.dust, vat.dustLayout.width, vat.dustLayout.height, settings.half));
    }
    Scene scene;
    scene.addMeshNode(vat.mesh);
    scene.nodes[0].name = settings.name;
    scene.extrasJson = format(R"({{"generator":"dawnforge vat","preset":"{}"}})", vatPresetName(settings.preset));
    const std::vector<std::byte> glb = encodeGlb(scene, {.primitivePerMaterial = false});  // one slot for the Labs material
    for (const auto& [suffix, bytes] : textures) writeFileAtomically(dir / (settings.name + suffix), bytes);
    writeFileAtomically(dir / (settings.name + "_mesh.glb"), glb);
    writeFileAtomically(dir / (settings.name + "_data.json"), std::string_view(vat.dataJson));
}

}  // namespace dawnforge::exporters
