// The overlook maps (overlook.hpp): vertical rays through Embree, stored as OpenEXR.
#include <dawnforge/bake/overlook.hpp>
#include <dawnforge/bake/ray_scene.hpp>

#include <dawnforge/core/atomic_file.hpp>
#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>

#include <ImfChannelList.h>
#include <ImfDoubleAttribute.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStdIO.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace dawnforge::bake {

namespace {
constexpr std::uint32_t kBuildingMask = 2, kGroundMask = 4;
constexpr int kMaxOverlookSize = 8192;
const char* const kChannels[3] = {"Z", "ground", "roof"};
}  // namespace

OverlookMap bakeOverlook(std::span<const OverlookMesh> meshes, double texel) {
    DAWNFORGE_ASSERT(texel > 0.0, "bakeOverlook(): the texel must be positive");
    OverlookMap map;
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    std::vector<RayGeometry> geometries;
    for (const OverlookMesh& m : meshes) {
        for (const glm::vec3& p : m.mesh->positions) lo = glm::min(lo, glm::dvec3(p)), hi = glm::max(hi, glm::dvec3(p));
        geometries.push_back({m.mesh->positions, m.mesh->indices, m.building ? kBuildingMask : kGroundMask});
    }
    if (lo.x > hi.x) lo = hi = glm::dvec3(0.0);
    // Whole texels over the bounds, at most kMaxOverlookSize on a side (the texel grows to fit).
    map.texel = std::max(texel, std::max(hi.x - lo.x, hi.z - lo.z) / kMaxOverlookSize);
    map.width = std::max(1, int(std::ceil((hi.x - lo.x) / map.texel)));
    map.height = std::max(1, int(std::ceil((hi.z - lo.z) / map.texel)));
    map.origin = {lo.x, lo.z};
    map.top = hi.y + 10.0;
    const std::size_t n = std::size_t(map.width) * std::size_t(map.height);
    map.depth.assign(n, 0.0f);
    map.ground.assign(n, kNoRoof);
    map.roof.assign(n, kNoRoof);
    const RayScene scene(geometries);
    const float range = float(map.top - lo.y + 10.0);
    tbb::parallel_for(0, map.height, [&](int row) {
        std::vector<Ray> rays(std::size_t(map.width));
        std::vector<Hit> hits(rays.size());
        for (int pass = 0; pass < 3; ++pass) {
            for (int col = 0; col < map.width; ++col) {
                Ray& r = rays[std::size_t(col)];
                r.origin = glm::vec3(float(map.origin.x + (col + 0.5) * map.texel), float(map.top), float(map.origin.y + (row + 0.5) * map.texel));
                r.direction = glm::vec3(0.0f, -1.0f, 0.0f);
                r.tFar = range;
                r.mask = pass == 0 ? (kBuildingMask | kGroundMask) : pass == 1 ? kGroundMask : kBuildingMask;
            }
            scene.intersect(rays, hits);
            for (int col = 0; col < map.width; ++col) {
                const Hit& h = hits[std::size_t(col)];
                const std::size_t i = std::size_t(row) * std::size_t(map.width) + std::size_t(col);
                const bool hit = h.geometry != kNoHit;
                if (pass == 0) map.depth[i] = hit ? h.t : range;
                else (pass == 1 ? map.ground : map.roof)[i] = hit ? float(map.top) - h.t : kNoRoof;
            }
        }
    });
    return map;
}

void writeOverlook(const OverlookMap& map, const std::filesystem::path& file) {
    Imf::Header header(map.width, map.height);
    header.compression() = Imf::ZIP_COMPRESSION;
    header.lineOrder() = Imf::INCREASING_Y;
    for (const char* c : kChannels) header.channels().insert(c, Imf::Channel(Imf::FLOAT));
    header.insert("dawnforge.x0", Imf::DoubleAttribute(map.origin.x));
    header.insert("dawnforge.z0", Imf::DoubleAttribute(map.origin.y));
    header.insert("dawnforge.texel", Imf::DoubleAttribute(map.texel));
    header.insert("dawnforge.top", Imf::DoubleAttribute(map.top));
    Imf::FrameBuffer frame;
    const std::vector<float>* planes[3] = {&map.depth, &map.ground, &map.roof};
    for (int c = 0; c < 3; ++c)
        frame.insert(kChannels[c], Imf::Slice(Imf::FLOAT, const_cast<char*>(reinterpret_cast<const char*>(planes[c]->data())), sizeof(float),
                                               sizeof(float) * std::size_t(map.width)));
    Imf::StdOSStream out;
    {
        Imf::OutputFile exr(out, header, 1);  // one thread: the bytes do not depend on a pool
        exr.setFrameBuffer(frame);
        exr.writePixels(map.height);
    }
    const std::string bytes = out.str();
    writeFileAtomically(file, std::as_bytes(std::span(bytes.data(), bytes.size())));
}

OverlookMap readOverlook(const std::filesystem::path& file) {
    if (!std::filesystem::exists(file)) throw InputError(format("{}: no such file", file.string()));
    OverlookMap map;
    try {
        Imf::InputFile in(file.c_str(), 1);
        const Imf::Header& header = in.header();
        const Imath::Box2i window = header.dataWindow();
        map.width = window.max.x - window.min.x + 1;
        map.height = window.max.y - window.min.y + 1;
        const auto attribute = [&](const char* name) {
            const auto* a = header.findTypedAttribute<Imf::DoubleAttribute>(name);
            if (!a) throw InputError(format("{}: no {} attribute: not a dawnforge overlook", file.string(), name));
            return a->value();
        };
        map.origin = {attribute("dawnforge.x0"), attribute("dawnforge.z0")};
        map.texel = attribute("dawnforge.texel");
        map.top = attribute("dawnforge.top");
        if (map.width < 1 || map.height < 1 || map.width > kMaxOverlookSize || map.height > kMaxOverlookSize || !(map.texel > 0.0))
            throw InputError(format("{}: {} x {} texels of {} m: not a dawnforge overlook", file.string(), map.width, map.height, map.texel));
        const std::size_t n = std::size_t(map.width) * std::size_t(map.height);
        std::vector<float>* planes[3] = {&map.depth, &map.ground, &map.roof};
        Imf::FrameBuffer frame;
        for (int c = 0; c < 3; ++c) {
            if (!header.channels().findChannel(kChannels[c]))
                throw InputError(format("{}: no {} channel: not a dawnforge overlook", file.string(), kChannels[c]));
            planes[c]->assign(n, 0.0f);
            char* base = reinterpret_cast<char*>(planes[c]->data()) -
                         (std::ptrdiff_t(window.min.x) + std::ptrdiff_t(window.min.y) * map.width) * std::ptrdiff_t(sizeof(float));
            frame.insert(kChannels[c], Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * std::size_t(map.width)));
        }
        in.setFrameBuffer(frame);
        in.readPixels(window.min.y, window.max.y);
    } catch (const InputError&) {
        throw;
    } catch (const std::exception& e) {
        throw InputError(format("{}: {}", file.string(), oneLine(e.what())));
    }
    return map;
}

}  // namespace dawnforge::bake
