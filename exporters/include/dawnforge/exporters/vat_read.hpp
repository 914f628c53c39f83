#pragma once
// Reading a VAT back (what writeVat wrote: DIR/<name>_pos.exr, _rot.exr, _mesh.glb and
// _data.json), checked for consistency, for the runtime that plays it.
#include <dawnforge/core/mesh.hpp>
#include <dawnforge/exporters/vat.hpp>

#include <glm/vec3.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace dawnforge::exporters {

struct VatFile {
    std::string name;
    VatPreset preset = VatPreset::Native;
    VatLayout layout;
    double fps = 0.0;
    bool half = false;                       // the EXRs store half floats (the values here are exact)
    std::vector<float> position, rotation;   // RGBA float, row 0 at the top, width × height
    // The _mesh.glb in world space (glTF axes, metres). pieceIds are always filled (from
    // _PIECE_ID, or from the lookup UV in uv1 when a foreign exporter left them out); the two
    // degenerate data triangles of the Unity/Unreal presets are removed.
    Mesh mesh;
    glm::dvec3 boundsMin{0.0}, boundsMax{0.0};  // _data.json "bounds": engine axes and units
    // <name>_dust.exr when _data.json's "dust" names it: `puffs` over 2 × frames (vat.hpp).
    std::size_t dustPuffs = 0;
    VatLayout dustLayout;
    std::vector<float> dust;
};

// Reads DIR/<name>_{pos.exr,rot.exr,mesh.glb,data.json} and _dust.exr when the data names it. Throws InputError naming the file
// and the problem when a file is missing or unreadable; the JSON is not a dawnforge.vat;
// W, R, height, frames and pieces disagree; an EXR is not W × height or lacks R, G, B, A;
// the mesh's piece count is not "pieces", a vertex's lookup UV (TEXCOORD_1) is not the texel
// centre of its piece in frame 0 (row < R); or any value is not finite.
VatFile readVat(const std::filesystem::path& dir, const std::string& name);

// The names of the VATs in a folder (each <name>_data.json), sorted. Throws InputError if
// `dir` is not a folder.
std::vector<std::string> listVats(const std::filesystem::path& dir);

}  // namespace dawnforge::exporters
