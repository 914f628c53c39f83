#include <dawnforge/exporters/material_images.hpp>

#include <dawnforge/core/atomic_file.hpp>
#include <dawnforge/core/error.hpp>
#include <dawnforge/core/leaves.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/material_paint.hpp>
#include <dawnforge/core/materials.hpp>
#include <dawnforge/core/read_file.hpp>
#include <dawnforge/exporters/image.hpp>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <mutex>

namespace dawnforge::exporters {

namespace {

std::uint8_t toByte(float x) { return std::uint8_t(std::clamp(int(x * 255.0f + 0.5f), 0, 255)); }

// The tile at texel centres, one repeat across the image; row 0 (glTF's v = 0) is v = 0.
Image paintImage(int material, int variant) {
    const int n = kMaterialImageSize;
    Image image{n, n, std::vector<std::uint8_t>(std::size_t(n) * n * 4, 255)};
    tbb::parallel_for(tbb::blocked_range<int>(0, n, 16), [&](const tbb::blocked_range<int>& rows) {
        for (int y = rows.begin(); y < rows.end(); ++y)
            for (int x = 0; x < n; ++x) {
                const glm::vec3 c = paintMaterial(material, variant, (float(x) + 0.5f) / float(n), (float(y) + 0.5f) / float(n));
                std::uint8_t* out = &image.rgba[(std::size_t(y) * n + x) * 4];
                out[0] = toByte(c.r), out[1] = toByte(c.g), out[2] = toByte(c.b);
            }
    });
    return image;
}

// Level 0 of the runtime's leaf picture, as it is: sRGB colour, alpha the leaves' coverage.
Image leafImage() { return {kLeafSize, kLeafSize, makeLeafImage().rgba[0]}; }

bool hasVariants(int material) { return material < kMaterialCount && materialHasVariants(material); }

int slot(int material, int variant) { return material * 4 + (hasVariants(material) ? variant : 0); }

void checkKey(int material, int variant) {
    DAWNFORGE_ASSERT(material >= 0 && material <= kLeafCards && variant >= 0 && variant < 4, "no such material image");
}

}  // namespace

std::string materialImageName(int material, int variant) {
    checkKey(material, variant);
    std::string name = material == kLeafCards ? "leaves" : materialName(std::uint8_t(material));
    if (hasVariants(material)) {
        name += '_';
        name += char('0' + variant);
    }
    name += ".png";
    return name;
}

const std::vector<std::byte>& materialImagePng(int material, int variant) {
    checkKey(material, variant);
    static std::array<std::vector<std::byte>, (kLeafCards + 1) * 4> cache;
    static std::array<std::once_flag, (kLeafCards + 1) * 4> made;
    const int k = slot(material, variant);
    std::call_once(made[std::size_t(k)], [&] {
        cache[std::size_t(k)] = encodePng(material == kLeafCards ? leafImage() : paintImage(material, variant));
    });
    return cache[std::size_t(k)];
}

glm::vec3 leafMeanColour() {
    const std::vector<std::uint8_t> rgba = makeLeafImage().rgba[0];
    const auto linear = [](std::uint8_t c) { const double s = c / 255.0; return s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4); };
    glm::dvec3 sum(0.0);
    double weight = 0.0;
    for (std::size_t i = 0; i < rgba.size(); i += 4) {
        const double a = rgba[i + 3] / 255.0;
        sum += a * glm::dvec3(linear(rgba[i]), linear(rgba[i + 1]), linear(rgba[i + 2]));
        weight += a;
    }
    return glm::vec3(sum / weight);
}

int writeMaterialImages(const std::filesystem::path& dir) {
    std::error_code made;
    std::filesystem::create_directories(dir, made);
    if (made) throw InputError(format("{}: cannot create the folder: {}", dir.string(), made.message()));
    int written = 0;
    for (int material = 0; material <= kLeafCards; ++material)
        for (int variant = 0; variant < (hasVariants(material) ? 4 : 1); ++variant) {
            const std::filesystem::path file = dir / materialImageName(material, variant);
            const std::vector<std::byte>& png = materialImagePng(material, variant);
            std::error_code ec;
            if (std::filesystem::file_size(file, ec) == png.size() && !ec && readBinaryFile(file) == png) continue;
            AtomicFile out(file);
            out.stream().write(reinterpret_cast<const char*>(png.data()), std::streamsize(png.size()));
            out.commit();
            ++written;
        }
    return written;
}

}  // namespace dawnforge::exporters
