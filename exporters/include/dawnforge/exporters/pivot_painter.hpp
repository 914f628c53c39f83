#pragma once
// Pivot Painter 2 textures: per element of a node hierarchy (each mesh node an element, its
// nearest mesh ancestor its parent), its pivot, parent, X axis and extent, one texel each,
// and a UV set (TEXCOORD_1) that points every vertex of an element at its texel, so a
// vertex shader can move many elements with no CPU work. Layout as Epic's Pivot Painter 2
// and the SideFX Labs node write it (notes: shared/notes/lighting-anchors.md; the sources read
// are listed in ARCHITECTURE.md, exporters/):
//
//   texel of element i: (i mod W, i div W), row 0 at the top; W = ceil(√n), H = ceil(n / W);
//   TEXCOORD_1 of its vertices: ((i mod W + 0.5) / W, (i div W + 0.5) / H).
//
// `unreal`: centimetres, Z up, (x, y, z) ↦ 100·(x, z, y) as Unreal's glTF importer maps ours.
//   Texture 1, RGBA half EXR: RGB the pivot, A the parent's index as Unreal's
//   ms_PivotPainter2_UnpackIntegerAsFloat reads it: the half whose bits are index + 1024 (a
//   root is its own parent); at most 30,720 elements (bits 0x7BFF, the largest finite half).
//   Texture 2, RGBA8 PNG, linear: RGB the unit X axis as round((v · 0.5 + 0.5) · 255), A the
//   extent along it as round(clamp(extent / 2048, 1/2048, 1) · 255) (8 to 2048 cm).
// `native`: metres, our axes (+Y up), both textures RGBA float EXR: pivot and parent index as
//   a plain number; X axis and extent in metres. Any number of elements up to 16384².
#include <dawnforge/core/import.hpp>
#include <dawnforge/core/mesh.hpp>

#include <cstddef>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace dawnforge::exporters {

enum class PivotPreset { Unreal, Native };
std::optional<PivotPreset> parsePivotPreset(std::string_view name);
std::string_view pivotPresetName(PivotPreset preset);

inline constexpr std::size_t kPivotUnrealMaxElements = 30720;

struct PivotElement {
    std::string name;
    int parent = 0;             // index; a root's is its own
    int depth = 0;              // 0 for a root
    glm::dvec3 pivot{0.0};      // metres, our axes: the node's origin
    glm::dvec3 xAxis{1, 0, 0};  // unit: the node's +X
    double extent = 0.0;        // metres: the element's size along xAxis
};

struct PivotPainter {
    PivotPreset preset = PivotPreset::Unreal;
    std::vector<PivotElement> elements;  // in the file's node order (a parent before its children)
    int levels = 0;                      // the deepest element's depth + 1
    int width = 0, height = 0;
    std::vector<float> pivots;  // texture 1, RGBA per texel, as written
    std::vector<float> axes;    // texture 2, RGBA per texel: [0, 1] for unreal (written as bytes), metres for native
    Mesh mesh;                  // every element's triangles in the file's space, TEXCOORD_1 set
};

// Throws InputError naming `source` when there is no hierarchy (no element has a parent),
// when the preset cannot hold the elements or a pivot (unreal: 655 m from the origin, the
// largest half float in cm), or when an element is scaled to nothing along X.
PivotPainter buildPivotPainter(std::span<const MeshNode> nodes, PivotPreset preset, const std::string& source);

// DIR/NAME_pivots.exr (texture 1), DIR/NAME_axes.png (unreal) or DIR/NAME_axes.exr (native),
// DIR/NAME.glb (the mesh) and DIR/NAME_pivots.json (the layout and every element), each
// written whole or not at all.
void writePivotPainter(const PivotPainter& painter, const std::filesystem::path& dir, const std::string& name);

}  // namespace dawnforge::exporters
