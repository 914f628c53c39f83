// Reading CITY_DIR/bake/ (bake_folder.hpp).
#include <dawnforge/bake/bake_folder.hpp>

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/read_file.hpp>
#include <dawnforge/core/seed.hpp>
#include <dawnforge/exporters/image.hpp>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>

namespace dawnforge::bake {

std::uint64_t hashFileBytes(std::span<const std::byte> bytes) {
    std::uint64_t h = mix64(0x6461776e666f7267ull ^ bytes.size());
    std::size_t i = 0;
    for (; i + 8 <= bytes.size(); i += 8) {
        std::uint64_t word = 0;
        for (int k = 7; k >= 0; --k) word = (word << 8) | std::uint64_t(bytes[i + std::size_t(k)]);
        h = mix64(h ^ word) + 0x9e3779b97f4a7c15ull;
    }
    std::uint64_t tail = 0;
    for (std::size_t k = bytes.size(); k-- > i;) tail = (tail << 8) | std::uint64_t(bytes[k]);
    return mix64(h ^ tail ^ (std::uint64_t(bytes.size() - i) << 56));
}

std::string hashText(std::uint64_t hash) {
    static const char* digits = "0123456789abcdef";
    std::string s(16, '0');
    for (int i = 15; i >= 0; --i, hash >>= 4) s[std::size_t(i)] = digits[hash & 15u];
    return s;
}

bool hasBake(const std::filesystem::path& cityDir) { return std::filesystem::exists(cityDir / "bake" / "bake.json"); }

BakeFolder readBake(const std::filesystem::path& cityDir, std::span<const std::byte> cityGlb) {
    const std::filesystem::path dir = cityDir / "bake", manifestFile = dir / "bake.json";
    const std::string where = manifestFile.string();
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(readTextFile(manifestFile));
    } catch (const nlohmann::json::exception& e) {
        throw InputError(format("{}: {}", where, oneLine(e.what())));
    }
    BakeFolder folder;
    try {
        if (j.value("format", "") != "dawnforge.bake" || j.value("version", 0) != 1)
            throw InputError(format("{}: not a dawnforge bake (format dawnforge.bake, version 1)", where));
        const std::string want = j.at("city_glb").at("hash").get<std::string>();
        const std::string have = hashText(hashFileBytes(cityGlb));
        if (want != have)
            throw InputError(format("{}: baked from another city.glb (hash {}, this city.glb has {}): bake this city again", where, want, have));
        for (const nlohmann::json& r : j.at("receivers")) {
            BakedReceiver out;
            out.name = r.at("name").get<std::string>();
            const std::filesystem::path png = dir / r.at("lightmap").get<std::string>(), uvFile = dir / r.at("uv").get<std::string>();
            exporters::Image image = exporters::readPng(png);
            const int w = r.at("size").at(0).get<int>(), h = r.at("size").at(1).get<int>();
            if (image.width != w || image.height != h)
                throw InputError(format("{}: {} x {} texels, but bake.json says {} x {}", png.string(), image.width, image.height, w, h));
            out.width = w, out.height = h;
            out.rgba = std::move(image.rgba);
            const std::vector<std::byte> bytes = readBinaryFile(uvFile);
            std::size_t vertices = 0;
            for (const nlohmann::json& m : r.at("meshes")) vertices += m.at("vertices").get<std::size_t>();
            if (bytes.size() != vertices * 8)
                throw InputError(format("{}: {} bytes, but {} vertices need {}", uvFile.string(), bytes.size(), vertices, vertices * 8));
            std::size_t offset = 0;
            for (const nlohmann::json& m : r.at("meshes")) {
                BakedMesh mesh;
                mesh.node = m.at("node").get<std::string>();
                mesh.uv.resize(m.at("vertices").get<std::size_t>());
                std::memcpy(mesh.uv.data(), bytes.data() + offset, mesh.uv.size() * 8);
                offset += mesh.uv.size() * 8;
                for (const glm::vec2& uv : mesh.uv)
                    if (!std::isfinite(uv.x) || !std::isfinite(uv.y))
                        throw InputError(format("{}: a UV that is not finite", uvFile.string()));
                out.meshes.push_back(std::move(mesh));
            }
            folder.receivers.push_back(std::move(out));
        }
        if (j.contains("overlook")) folder.overlook = readOverlook(dir / j["overlook"].get<std::string>());
    } catch (const nlohmann::json::exception& e) {
        throw InputError(format("{}: {}", where, oneLine(e.what())));
    }
    return folder;
}

}  // namespace dawnforge::bake
