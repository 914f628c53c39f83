#pragma once
// Vertex animation textures for rigid pieces, laid out like SideFX Labs VAT 3.0
// "Rigid-Body Dynamics" (ARCHITECTURE.md, File formats; what was verified against the
// Labs sources is listed there and in the README):
//   W = min(maxWidth, pieces), R = ceil(pieces / W) rows per frame, height = R × frames;
//   piece j at frame k is the texel at column j mod W, row k·R + floor(j / W) from the top.
//   Position RGBA = (pivot in engine axes and units, 0.25 × dropped component index).
//   Rotation RGBA = (the quaternion with its largest component made positive and dropped,
//   w in its slot, in engine axes; signed turns to the next frame).
//   The mesh (glTF axes, metres) carries the lookup UV (texel centre) in TEXCOORD_1 and the
//   pivot (Houdini axes, engine units) in TEXCOORD_2/3, V flipped to glTF's top-left origin.
//   Non-HDR (VatFormat::Ldr, the Labs "Non-HDR" form, RGBA 8 in the engine): positions are
//   (pos.rgb + 0.01 × pos2.rgb) of the encoded bounds' box (a second texture for precision),
//   rotations (rot − 0.5) × 2, the turns over the largest turns per frame the bounds carry.
#include <dawnforge/core/mesh.hpp>

#include <cstddef>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace dawnforge::exporters {

enum class VatPreset {
    Native,  // metres, +Y up: what the dawnforge runtime plays
    Unreal,  // Z-up centimetres, the Labs Unreal axis and sign conventions
    Unity,   // left-handed (x mirrored), metres, the Labs Unity conventions
};
std::optional<VatPreset> parseVatPreset(std::string_view name);
std::string_view vatPresetName(VatPreset preset);

enum class VatFormat {
    Hdr,  // OpenEXR, RGBA float (or half)
    Ldr,  // the Labs Non-HDR form: three 8-bit RGBA PNGs (pos, pos2, rot), for the engine presets
};
std::optional<VatFormat> parseVatFormat(std::string_view name);
std::string_view vatFormatName(VatFormat format);

struct VatSettings {
    VatPreset preset = VatPreset::Native;
    VatFormat format = VatFormat::Hdr;
    bool half = false;      // HDR: RGBA16F instead of RGBA32F
    bool singlePositionTexture = false;  // Ldr: no _pos2 (positions to 1/510 of the bounds)
    int maxWidth = 1024;    // texture width limit (1 to 8192)
    std::string name = "vat";
    // Unreal: the pivots unencoded in 32-bit UVs (exact; the mesh needs Unreal's "Use Full
    // Precision UVs") instead of the Labs "Very High" form for its default 16-bit UVs.
    bool fullPrecisionUvs = false;
};

inline constexpr int kVatMaxTextureSize = 8192;

struct VatLayout {
    std::size_t pieces = 0;
    int frames = 0;
    int width = 0;         // W
    int rowsPerFrame = 0;  // R
    int height = 0;        // R × frames
};

// The layout for `pieces` and `frames`; throws InputError when the texture would be larger
// than 8192 in either direction, saying how many frames would fit.
VatLayout vatLayout(std::size_t pieces, int frames, int maxWidth);

// The animation to bake: the rest meshes (relative to each piece's pivot, world axes,
// metres) and transforms as in transforms.bin (frames × pieces × px py pz qx qy qz qw).
struct VatAnimation {
    std::span<const Mesh> pieces;
    std::span<const float> transforms;
    int frames = 0;
    double fps = 0.0;
    // Optional, frames × pieces: signed turns from each frame to the next along the
    // simulated path (the simulation's turns.bin). Empty: the shortest way between poses,
    // which cannot show more than half a turn per frame.
    std::span<const float> turns = {};
    // Optional: frames × dustPuffs × (x y z size opacity), the simulation's dust.bin, baked
    // beside the pieces into <name>_dust.exr (HDR only).
    std::span<const float> dust = {};
    std::size_t dustPuffs = 0;
};

struct Vat {
    VatLayout layout;
    std::vector<float> position;  // RGBA per texel, row 0 at the top; rounded to half if settings.half,
    std::vector<float> rotation;  // to k / 255 for Ldr
    std::vector<float> position2; // Ldr: the positions' hundredths; empty for Hdr
    Mesh mesh;                    // rest pose with the lookup and pivot channels (+ 2 data triangles for engines)
    glm::dvec3 boundsMin{0.0}, boundsMax{0.0};  // of every vertex over the animation, engine axes and units
    double maxTurnsPerFrame = 0.0;
    // Worst error the stored precision introduced, decoded and compared with the input:
    double maxPositionError = 0.0;  // m, pivot positions
    double maxRotationError = 0.0;  // rad, orientations
    double maxPivotError = 0.0;     // m, how far the pivot UVs move a pivot (Unreal's Very High form)
    double maxScaleError = 0.0;     // Ldr: |decoded piece scale − 1| (8-bit position alpha)
    double maxVertexError = 0.0;    // m, bound on any vertex (position + rotation × piece radius)
    std::string dataJson;           // <name>_data.json
    // Dust (vat_dust.cpp): RGBA per texel, the pieces' layout for the puffs over 2 × frames
    // (centre and size, then opacity); empty without dust.
    VatLayout dustLayout;
    std::vector<float> dust;
};

// Encodes `animation` (checked: piece count and transforms size agree, at least one frame,
// fps > 0, finite values). Throws InputError on bad input.
Vat encodeVat(const VatAnimation& animation, const VatSettings& settings);

// Writes DIR/<name>_pos.exr, <name>_rot.exr (OpenEXR, PIZ, RGBA float or half, row 0 at the
// top; Ldr: <name>_pos.png, _pos2.png, _rot.png, 8-bit RGBA), <name>_dust.exr when there is
// dust, <name>_mesh.glb and <name>_data.json, each atomically.
void writeVat(const Vat& vat, const VatSettings& settings, const std::filesystem::path& dir);

}  // namespace dawnforge::exporters
