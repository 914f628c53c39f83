#include <dawnforge/exporters/image.hpp>

#include <dawnforge/core/atomic_file.hpp>
#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>

#include <stb_image.h>
#include <stb_image_write.h>

#include <cstring>

namespace dawnforge::exporters {

std::vector<std::byte> encodePng(const Image& image) {
    DAWNFORGE_ASSERT(image.width > 0 && image.height > 0 &&
                         image.rgba.size() == std::size_t(image.width) * std::size_t(image.height) * 4,
                     "image size and pixel count disagree");
    std::vector<std::byte> bytes;
    const auto append = [](void* context, void* data, int size) {
        auto* out = static_cast<std::vector<std::byte>*>(context);
        const auto* begin = static_cast<const std::byte*>(data);
        out->insert(out->end(), begin, begin + size);
    };
    if (!stbi_write_png_to_func(append, &bytes, image.width, image.height, 4, image.rgba.data(), image.width * 4))
        throw std::runtime_error("PNG encoding failed");
    return bytes;
}

void writePng(const Image& image, const std::filesystem::path& file) {
    writeFileAtomically(file, encodePng(image));
}

Image readPng(const std::filesystem::path& file) {
    int w = 0, h = 0, channels = 0;
    stbi_uc* pixels = stbi_load(file.string().c_str(), &w, &h, &channels, 4);
    if (!pixels) throw InputError(format("{}: cannot read as an image ({})", file.string(), stbi_failure_reason()));
    Image image{w, h, std::vector<std::uint8_t>(pixels, pixels + std::size_t(w) * std::size_t(h) * 4)};
    stbi_image_free(pixels);
    return image;
}

}  // namespace dawnforge::exporters
