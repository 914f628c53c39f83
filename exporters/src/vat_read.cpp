// Reading a VAT back (vat_read.hpp): the layout rules of vat.hpp checked against every file.
#include <dawnforge/exporters/vat_read.hpp>

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/read_file.hpp>
#include <dawnforge/core/import.hpp>
#include <dawnforge/core/isolate.hpp>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <exception>
#include <fstream>
#include <memory>
#include <set>
#include <sstream>
#include <utility>

namespace dawnforge::exporters {

namespace {

using Json = nlohmann::json;


const Json& member(const Json& object, const char* key, const std::string& file) {
    const auto it = object.find(key);
    if (it == object.end()) throw InputError(format("{}: \"{}\" is missing", file, key));
    return *it;
}

std::int64_t integer(const Json& object, const char* key, const std::string& file, std::int64_t lo, std::int64_t hi) {
    const Json& j = member(object, key, file);
    if (!j.is_number_integer()) throw InputError(format("{}: \"{}\" must be an integer", file, key));
    const bool inRange = j.is_number_unsigned() ? j.get<std::uint64_t>() <= std::uint64_t(hi) && std::int64_t(j.get<std::uint64_t>()) >= lo
                                                : j.get<std::int64_t>() >= lo && j.get<std::int64_t>() <= hi;
    if (!inRange) throw InputError(format("{}: \"{}\" must be in [{}, {}] (got {})", file, key, lo, hi, j.dump()));
    return j.get<std::int64_t>();
}

glm::dvec3 vec3(const Json& j, const std::string& what, const std::string& file) {
    if (!j.is_array() || j.size() != 3 || !std::all_of(j.begin(), j.end(), [](const Json& v) { return v.is_number(); }))
        throw InputError(format("{}: \"{}\" must be an array of three numbers", file, what));
    const glm::dvec3 v(j[0].get<double>(), j[1].get<double>(), j[2].get<double>());
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
        throw InputError(format("{}: \"{}\" holds a value that is not finite", file, what));
    return v;
}

// RGBA as float (OpenEXR converts half exactly), row 0 = the first row in the file (the top).
// In this process: the isolated reader below runs it in a child.
std::vector<float> decodeExr(const std::string& file, const VatLayout& layout, bool& half) {
    std::vector<float> rgba;
    try {
        // No thread pool: in a forked child, a pool the parent started has no threads.
        Imf::InputFile in(file.c_str(), 0);
        const Imf::Header& header = in.header();
        const Imath::Box2i window = header.dataWindow();
        const long long width = (long long)window.max.x - window.min.x + 1;
        const long long height = (long long)window.max.y - window.min.y + 1;
        if (width != layout.width || height != layout.height)
            throw InputError(format("{}: the texture is {} × {}, but the VAT's data.json says W × height = {} × {}", file,
                                    width, height, layout.width, layout.height));
        const char* names[4] = {"R", "G", "B", "A"};
        for (const char* c : names)
            if (!header.channels().findChannel(c))
                throw InputError(format("{}: channel {} is missing (a VAT texture has R, G, B and A)", file, c));
        half = header.channels().findChannel("R")->type == Imf::HALF;
        rgba.assign(std::size_t(width) * std::size_t(height) * 4, 0.0f);
        char* base = reinterpret_cast<char*>(rgba.data()) -
                     (std::ptrdiff_t(window.min.x) + std::ptrdiff_t(window.min.y) * std::ptrdiff_t(width)) * std::ptrdiff_t(4 * sizeof(float));
        Imf::FrameBuffer frame;
        for (int c = 0; c < 4; ++c)
            frame.insert(names[c], Imf::Slice(Imf::FLOAT, base + std::size_t(c) * sizeof(float), 4 * sizeof(float),
                                              4 * sizeof(float) * std::size_t(width)));
        in.setFrameBuffer(frame);
        in.readPixels(window.min.y, window.max.y);
    } catch (const InputError&) {
        throw;
    } catch (const std::exception& e) {
        throw InputError(format("{}: not a readable OpenEXR file: {}", file, oneLine(e.what())));
    }
    return rgba;
}

// decodeExr in a child process (core/isolate.hpp): a user hands in a VAT folder, and OpenEXR
// is a large parser of binary data. The answer is the half flag and exactly the layout's texels.
std::vector<float> readExr(const std::filesystem::path& path, const VatLayout& layout, bool& half) {
    const std::string file = path.string();
    const std::size_t texels = std::size_t(layout.width) * std::size_t(layout.height);
    std::vector<float> rgba;
    readIsolated(
        path, "EXR",
        [&] {
            auto decoded = std::make_shared<std::vector<float>>();
            bool isHalf = false;
            *decoded = decodeExr(file, layout, isHalf);
            return Answer{1 + decoded->size() * sizeof(float), [decoded, isHalf](AnswerSink& sink) {
                              const char flag = isHalf ? 1 : 0;
                              sink.write(&flag, 1);
                              sink.write(decoded->data(), decoded->size() * sizeof(float));
                          }};
        },
        [&](AnswerSource& answer) {
            if (answer.left() != 1 + texels * 4 * sizeof(float))
                throw InputError(format("{}: the EXR reader's answer is damaged ({} bytes for {} texels)", file,
                                        answer.left(), texels));
            char flag = 0;
            answer.read(&flag, 1);
            half = flag != 0;
            rgba.resize(texels * 4);
            answer.read(rgba.data(), rgba.size() * sizeof(float));
        });
    for (std::size_t i = 0; i < rgba.size(); ++i)
        if (!std::isfinite(rgba[i]))
            throw InputError(format("{}: texel ({}, {}) holds a value that is not finite", file,
                                    (i / 4) % std::size_t(layout.width), (i / 4) / std::size_t(layout.width)));
    return rgba;
}

bool finite(const std::vector<glm::vec2>& v) {
    return std::all_of(v.begin(), v.end(), [](const glm::vec2& p) { return std::isfinite(p.x) && std::isfinite(p.y); });
}

// The piece whose frame-0 texel centre `uv` is (glTF V from the top), or -1.
long long pieceAt(const glm::vec2& uv, const VatLayout& layout) {
    const double x = double(uv.x) * layout.width - 0.5, y = double(uv.y) * layout.height - 0.5;
    const double column = std::round(x), row = std::round(y);
    // 0.01 texel: float rounding of (i + 0.5) / size stays far below that up to 8192 texels.
    if (std::abs(x - column) > 0.01 || std::abs(y - row) > 0.01) return -1;
    if (column < 0 || column >= layout.width || row < 0 || row >= layout.rowsPerFrame) return -1;
    return (long long)(row) * layout.width + (long long)(column);
}

// The mesh without the vertices in `drop` (and the triangles that use them).
Mesh without(const Mesh& mesh, const std::vector<bool>& drop) {
    std::vector<std::uint32_t> remap(mesh.positions.size(), UINT32_MAX);
    Mesh out;
    out.name = mesh.name;
    const auto keep = [&](auto& dst, const auto& src) {
        if (src.empty()) return;
        for (std::size_t i = 0; i < src.size(); ++i)
            if (!drop[i]) dst.push_back(src[i]);
    };
    std::uint32_t next = 0;
    for (std::size_t i = 0; i < mesh.positions.size(); ++i)
        if (!drop[i]) remap[i] = next++;
    keep(out.positions, mesh.positions);
    keep(out.normals, mesh.normals);
    keep(out.uv0, mesh.uv0);
    keep(out.uv1, mesh.uv1);
    keep(out.uv2, mesh.uv2);
    keep(out.uv3, mesh.uv3);
    keep(out.materialIds, mesh.materialIds);
    keep(out.pieceIds, mesh.pieceIds);
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const std::uint32_t a = remap[mesh.indices[t]], b = remap[mesh.indices[t + 1]], c = remap[mesh.indices[t + 2]];
        if (a == UINT32_MAX || b == UINT32_MAX || c == UINT32_MAX) continue;
        out.indices.insert(out.indices.end(), {a, b, c});
    }
    return out;
}

// The mesh checked against the layout: one piece per lookup texel, `pieces` of them.
Mesh checkedMesh(Mesh mesh, const VatLayout& layout, VatPreset preset, const std::string& file) {
    const std::size_t n = mesh.positions.size();
    if (mesh.uv1.size() != n)
        throw InputError(format("{}: the mesh has no lookup UVs (TEXCOORD_1), so it cannot play a VAT", file));
    if (!finite(mesh.uv0) || !finite(mesh.uv1) || !finite(mesh.uv2) || !finite(mesh.uv3) ||
        !std::all_of(mesh.normals.begin(), mesh.normals.end(),
                     [](const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }))
        throw InputError(format("{}: a normal or texture coordinate is not finite", file));
    const bool hasIds = mesh.pieceIds.size() == n;
    // The Unity/Unreal presets append two degenerate triangles that carry the bounds
    // (piece id = pieces, lookup UV (0, 1)); the runtime does not draw them.
    std::vector<bool> data(n, false);
    std::size_t dataVertices = 0;
    if (preset != VatPreset::Native)
        for (std::size_t i = 0; i < n; ++i) {
            data[i] = hasIds ? mesh.pieceIds[i] == layout.pieces : mesh.uv1[i] == glm::vec2(0.0f, 1.0f);
            dataVertices += data[i];
        }

    std::size_t count = 0;
    std::vector<long long> lookup(n, -1);
    if (hasIds) {
        std::uint32_t top = 0;
        bool any = false;
        for (std::size_t i = 0; i < n; ++i) {
            if (data[i]) continue;
            top = std::max(top, mesh.pieceIds[i]);
            any = true;
        }
        count = any ? std::size_t(top) + 1 : 0;
    } else {
        std::set<std::pair<float, float>> distinct;
        for (std::size_t i = 0; i < n; ++i)
            if (!data[i]) distinct.emplace(mesh.uv1[i].x, mesh.uv1[i].y);
        count = distinct.size();
    }
    if (count != layout.pieces)
        throw InputError(format("{}: the mesh has {} pieces ({}), but data.json says \"pieces\": {}", file, count,
                                hasIds ? "highest _PIECE_ID + 1" : "distinct TEXCOORD_1 lookup UVs", layout.pieces));
    for (std::size_t i = 0; i < n; ++i) {
        if (data[i]) continue;
        const long long j = pieceAt(mesh.uv1[i], layout);
        if (j < 0 || j >= (long long)layout.pieces)
            throw InputError(format("{}: vertex {} has lookup UV ({}, {}), which is not the centre of a piece's texel in "
                                    "frame 0 ({} × {} texels per frame, {} pieces)",
                                    file, i, mesh.uv1[i].x, mesh.uv1[i].y, layout.width, layout.rowsPerFrame, layout.pieces));
        if (hasIds && std::uint32_t(j) != mesh.pieceIds[i])
            throw InputError(format("{}: vertex {} belongs to piece {} but its lookup UV ({}, {}) is the texel of piece {}",
                                    file, i, mesh.pieceIds[i], mesh.uv1[i].x, mesh.uv1[i].y, j));
        lookup[i] = j;
    }
    if (!hasIds) {
        mesh.pieceIds.assign(n, 0);
        for (std::size_t i = 0; i < n; ++i) mesh.pieceIds[i] = data[i] ? std::uint32_t(layout.pieces) : std::uint32_t(lookup[i]);
    }
    if (dataVertices == 0) return mesh;
    Mesh drawn = without(mesh, data);
    if (drawn.indices.empty()) throw InputError(format("{}: the mesh has no triangles besides its data triangles", file));
    return drawn;
}

}  // namespace

namespace {

// The dust's texture when _data.json's "dust" names one: its layout must be the puffs' over
// 2 × frames at the stated W.
void readDust(const std::filesystem::path& dir, const Json& root, const std::string& file, VatFile& vat) {
    if (!root.contains("dust") || !root["dust"].is_object() || !root["dust"].contains("file") || root["dust"]["file"].is_null())
        return;
    const Json& d = root["dust"];
    const Json& name = member(d, "file", file);
    if (!name.is_string() || name.get<std::string>().find('/') != std::string::npos)
        throw InputError(format("{}: \"dust.file\" must be a file name beside it", file));
    const std::size_t puffs = std::size_t(integer(d, "puffs", file, 1, std::int64_t(kVatMaxTextureSize) * kVatMaxTextureSize));
    const int width = int(integer(d, "W", file, 1, kVatMaxTextureSize));
    VatLayout L = vatLayout(puffs, 2 * vat.layout.frames, width);
    if (L.width != width || L.height != integer(d, "height", file, 1, kVatMaxTextureSize))
        throw InputError(format("{}: \"dust\": W and height do not fit {} puffs over 2 × {} frames", file, puffs, vat.layout.frames));
    bool half = false;
    vat.dust = readExr(dir / name.get<std::string>(), L, half);
    L.frames = vat.layout.frames;
    vat.dustLayout = L;
    vat.dustPuffs = puffs;
}

}  // namespace

VatFile readVat(const std::filesystem::path& dir, const std::string& name) {
    const std::filesystem::path posPath = dir / (name + "_pos.exr"), rotPath = dir / (name + "_rot.exr"),
                                meshPath = dir / (name + "_mesh.glb"), dataPath = dir / (name + "_data.json");
    for (const std::filesystem::path& p : {dataPath, posPath, rotPath, meshPath}) {
        std::error_code ec;
        if (!std::filesystem::is_regular_file(p, ec))
            throw InputError(format("{}: missing (a VAT is {}_pos.exr, {}_rot.exr, {}_mesh.glb and {}_data.json in {})",
                                    p.string(), name, name, name, name, dir.string()));
    }

    const std::string file = dataPath.string();
    Json root;
    try {
        root = Json::parse(readTextFile(dataPath));
    } catch (const Json::exception& e) {
        throw InputError(format("{}: not valid JSON: {}", file, oneLine(e.what())));
    }
    if (!root.is_object() || !root.contains("format") || root["format"] != "dawnforge.vat")
        throw InputError(format("{}: not a VAT description (expected \"format\": \"dawnforge.vat\")", file));
    if (root.value("version", Json()) != 1)
        throw InputError(format("{}: unsupported version {} (expected 1)", file, root.value("version", Json()).dump()));

    VatFile vat;
    vat.name = name;
    const Json& preset = member(root, "preset", file);
    const auto parsed = preset.is_string() ? parseVatPreset(preset.get<std::string>()) : std::nullopt;
    if (!parsed) throw InputError(format("{}: \"preset\" is {}, expected native, unreal or unity", file, preset.dump()));
    vat.preset = *parsed;
    const Json& fps = member(root, "fps", file);
    if (!fps.is_number() || !(fps.get<double>() > 0.0) || !std::isfinite(fps.get<double>()))
        throw InputError(format("{}: \"fps\" must be a positive number (got {})", file, fps.dump()));
    vat.fps = fps.get<double>();

    VatLayout& L = vat.layout;
    L.pieces = std::size_t(integer(root, "pieces", file, 1, std::int64_t(kVatMaxTextureSize) * kVatMaxTextureSize));
    L.frames = int(integer(root, "frames", file, 1, kVatMaxTextureSize));
    L.width = int(integer(root, "W", file, 1, kVatMaxTextureSize));
    L.rowsPerFrame = int(integer(root, "R", file, 1, kVatMaxTextureSize));
    L.height = int(integer(root, "height", file, 1, kVatMaxTextureSize));
    if (std::size_t(L.width) > L.pieces)
        throw InputError(format("{}: \"W\" is {}, more than the {} pieces", file, L.width, L.pieces));
    const std::size_t rows = (L.pieces + std::size_t(L.width) - 1) / std::size_t(L.width);
    if (std::size_t(L.rowsPerFrame) != rows)
        throw InputError(format("{}: \"R\" is {}, but {} pieces at W = {} need {} rows per frame", file, L.rowsPerFrame,
                                L.pieces, L.width, rows));
    if (L.height != L.rowsPerFrame * L.frames)
        throw InputError(format("{}: \"height\" is {}, but R × frames = {} × {} = {}", file, L.height, L.rowsPerFrame,
                                L.frames, std::int64_t(L.rowsPerFrame) * L.frames));

    const Json& bounds = member(root, "bounds", file);
    if (!bounds.is_object()) throw InputError(format("{}: \"bounds\" must be an object {{\"min\": [...], \"max\": [...]}}", file));
    vat.boundsMin = vec3(member(bounds, "min", file), "bounds.min", file);
    vat.boundsMax = vec3(member(bounds, "max", file), "bounds.max", file);
    if (!(vat.boundsMin.x <= vat.boundsMax.x && vat.boundsMin.y <= vat.boundsMax.y && vat.boundsMin.z <= vat.boundsMax.z))
        throw InputError(format("{}: \"bounds\": min is above max", file));

    bool posHalf = false, rotHalf = false;
    vat.position = readExr(posPath, L, posHalf);
    vat.rotation = readExr(rotPath, L, rotHalf);
    vat.half = posHalf && rotHalf;
    vat.mesh = checkedMesh(loadMesh(meshPath), L, vat.preset, meshPath.string());
    readDust(dir, root, file, vat);
    return vat;
}

std::vector<std::string> listVats(const std::filesystem::path& dir) {
    std::error_code ec;
    if (!std::filesystem::is_directory(dir, ec))
        throw InputError(format("{}: not a folder (expected a folder of VATs, each <name>_data.json with its textures and mesh)",
                                dir.string()));
    const std::string suffix = "_data.json";
    std::vector<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
        const std::string file = entry.path().filename().string();
        if (file.size() > suffix.size() && file.compare(file.size() - suffix.size(), suffix.size(), suffix) == 0 &&
            entry.is_regular_file(ec))
            names.push_back(file.substr(0, file.size() - suffix.size()));
    }
    if (ec) throw InputError(format("{}: cannot list the folder: {}", dir.string(), ec.message()));
    std::sort(names.begin(), names.end());
    return names;
}

}  // namespace dawnforge::exporters
