// Pivot Painter 2 textures (pivot_painter.hpp says the layout and where it was read).
#include <dawnforge/exporters/pivot_painter.hpp>

#include <dawnforge/core/atomic_file.hpp>
#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/scene.hpp>
#include <dawnforge/exporters/gltf.hpp>
#include <dawnforge/exporters/image.hpp>

#include <Imath/half.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace dawnforge::exporters {

namespace {

constexpr int kMaxNativeSide = 16384;
constexpr double kUnrealExtentRange = 2048.0;  // cm: Epic's default, the Labs node's too
constexpr double kMaxHalf = 65504.0;           // the largest finite half float

// Unreal's axes and units: 100·(x, z, y).
glm::dvec3 toUnreal(const glm::dvec3& v, double scale) { return scale * glm::dvec3(v.x, v.z, v.y); }

// The half whose bits are index + 1024, as a float (exactly a half, so written as HALF it
// keeps those bits): what ms_PivotPainter2_UnpackIntegerAsFloat turns back into the index.
float indexAsHalfBits(int index) {
    Imath::half h;
    h.setBits(static_cast<unsigned short>(index + 1024));
    return float(h);
}

float byteLevel(double unit) { return float(std::lround(std::clamp(unit, 0.0, 1.0) * 255.0)) / 255.0f; }

PivotElement elementOf(const MeshNode& node, const std::vector<PivotElement>& earlier, int index,
                       const std::string& source) {
    PivotElement e;
    e.name = node.name;
    e.parent = node.parent >= 0 ? node.parent : index;
    e.depth = node.parent >= 0 ? earlier[std::size_t(node.parent)].depth + 1 : 0;
    const glm::dmat4 world(node.world);
    e.pivot = glm::dvec3(world[3]);
    const glm::dvec3 x(world[0]);
    if (!(glm::length(x) > 1e-9))
        throw InputError(format("{}: node '{}' is scaled to nothing along its X axis", source, node.name));
    e.xAxis = glm::normalize(x);
    double lo = std::numeric_limits<double>::max(), hi = -lo;
    for (const glm::vec3& p : node.mesh.positions) {
        const double along = glm::dot(glm::dvec3(world * glm::dvec4(glm::dvec3(p), 1.0)) - e.pivot, e.xAxis);
        lo = std::min(lo, along), hi = std::max(hi, along);
    }
    e.extent = hi - lo;
    return e;
}

void checkCount(std::size_t n, PivotPreset preset, const std::string& source) {
    if (preset == PivotPreset::Unreal && n > kPivotUnrealMaxElements)
        throw InputError(format("{}: {} elements; Unreal's Pivot Painter 2 holds at most {} (a parent index is the "
                                "bits of a half float, index + 1024 up to 0x7BFF); use --preset native",
                                source, n, kPivotUnrealMaxElements));
    if (n > std::size_t(kMaxNativeSide) * std::size_t(kMaxNativeSide))
        throw InputError(format("{}: {} elements do not fit a {}² texture", source, n, kMaxNativeSide));
}

// Texture 1 and 2 texels of one element, in the preset's encoding.
void writeTexels(PivotPainter& p, std::size_t i, const std::string& source) {
    const PivotElement& e = p.elements[i];
    float* pivot = p.pivots.data() + 4 * i;
    float* axis = p.axes.data() + 4 * i;
    if (p.preset == PivotPreset::Native) {
        const glm::dvec4 a(e.pivot, double(e.parent)), b(e.xAxis, e.extent);
        for (int k = 0; k < 4; ++k) pivot[k] = float(a[k]), axis[k] = float(b[k]);
        return;
    }
    const glm::dvec3 at = toUnreal(e.pivot, 100.0), x = toUnreal(e.xAxis, 1.0);
    if (std::max({std::abs(at.x), std::abs(at.y), std::abs(at.z)}) > kMaxHalf)
        throw InputError(format("{}: element '{}' pivots {:.0f} m from the origin; a half float holds 655 m (move the "
                                "mesh to the origin, or use --preset native)",
                                source, e.name, glm::length(e.pivot)));
    for (int k = 0; k < 3; ++k) pivot[k] = float(at[k]), axis[k] = byteLevel(x[k] * 0.5 + 0.5);
    pivot[3] = indexAsHalfBits(e.parent);
    axis[3] = byteLevel(std::clamp(100.0 * e.extent / kUnrealExtentRange, 1.0 / kUnrealExtentRange, 1.0));
}

}  // namespace

std::optional<PivotPreset> parsePivotPreset(std::string_view name) {
    if (name == "unreal") return PivotPreset::Unreal;
    if (name == "native") return PivotPreset::Native;
    return std::nullopt;
}

std::string_view pivotPresetName(PivotPreset preset) { return preset == PivotPreset::Native ? "native" : "unreal"; }

PivotPainter buildPivotPainter(std::span<const MeshNode> nodes, PivotPreset preset, const std::string& source) {
    const std::size_t n = nodes.size();
    checkCount(n, preset, source);
    if (std::none_of(nodes.begin(), nodes.end(), [](const MeshNode& node) { return node.parent >= 0; }))
        throw InputError(format("{}: no node hierarchy: none of its {} mesh node(s) is the child of another "
                                "(Pivot Painter moves children about their parents)",
                                source, n));
    PivotPainter p;
    p.preset = preset;
    p.width = int(std::ceil(std::sqrt(double(n))));
    p.height = int((n + std::size_t(p.width) - 1) / std::size_t(p.width));
    p.pivots.assign(std::size_t(p.width) * std::size_t(p.height) * 4, 0.0f);
    p.axes = p.pivots;
    for (std::size_t i = 0; i < n; ++i) {
        p.elements.push_back(elementOf(nodes[i], p.elements, int(i), source));
        p.levels = std::max(p.levels, p.elements.back().depth + 1);
        writeTexels(p, i, source);
        const glm::vec2 texel((float(i % std::size_t(p.width)) + 0.5f) / float(p.width),
                              (float(i / std::size_t(p.width)) + 0.5f) / float(p.height));
        Mesh part = nodes[i].mesh;
        part.uv1.assign(part.positions.size(), texel);
        appendMesh(p.mesh, part, nodes[i].world);
    }
    return p;
}

void writePivotPainter(const PivotPainter& p, const std::filesystem::path& dir, const std::string& name) {
    const bool native = p.preset == PivotPreset::Native;
    const std::vector<std::byte> pivots = encodeExr(p.pivots, p.width, p.height, !native);
    std::vector<std::byte> axes;
    if (native) {
        axes = encodeExr(p.axes, p.width, p.height, false);
    } else {
        Image image{p.width, p.height, std::vector<std::uint8_t>(p.axes.size())};
        for (std::size_t k = 0; k < p.axes.size(); ++k) image.rgba[k] = std::uint8_t(std::lround(p.axes[k] * 255.0f));
        axes = encodePng(image);
    }
    Scene scene;
    scene.addMeshNode(p.mesh);
    scene.nodes[0].name = name;
    scene.meshes[0].name = name;  // importers name the mesh after it (Blender showed "Mesh_0")
    scene.extrasJson = format(R"({{"generator":"dawnforge pivots","preset":"{}"}})", pivotPresetName(p.preset));
    const std::vector<std::byte> glb = encodeGlb(scene);

    nlohmann::ordered_json json{{"format", "dawnforge.pivots"}, {"version", 1}, {"preset", pivotPresetName(p.preset)},
                                {"width", p.width}, {"height", p.height}, {"uv_set", 1}};
    for (const PivotElement& e : p.elements) {
        json["elements"].push_back({{"name", e.name}, {"parent", e.parent}, {"depth", e.depth},
                                    {"pivot", {e.pivot.x, e.pivot.y, e.pivot.z}},
                                    {"x_axis", {e.xAxis.x, e.xAxis.y, e.xAxis.z}}, {"extent", e.extent}});
    }
    json["levels"] = p.levels;
    const std::string axesFile = name + (native ? "_axes.exr" : "_axes.png");
    json["files"] = {{"pivots", name + "_pivots.exr"}, {"axes", axesFile}, {"mesh", name + ".glb"}};

    ensureOutputDirectory(dir);
    writeFileAtomically(dir / (name + "_pivots.exr"), pivots);
    writeFileAtomically(dir / axesFile, axes);
    writeFileAtomically(dir / (name + ".glb"), glb);
    writeFileAtomically(dir / (name + "_pivots.json"), std::string_view(json.dump(2) + "\n"));
}

}  // namespace dawnforge::exporters
