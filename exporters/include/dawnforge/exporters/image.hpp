#pragma once
// 8-bit images: PNG in and out (stb); float textures out as OpenEXR. Rows run top to bottom, RGBA.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

namespace dawnforge::exporters {

struct Image {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> rgba;  // width × height × 4, row 0 at the top
};

// PNG bytes of `image` (zlib level fixed, so the same pixels give the same bytes).
std::vector<std::byte> encodePng(const Image& image);
// Writes `image` as PNG atomically; throws InputError if the file cannot be written.
void writePng(const Image& image, const std::filesystem::path& file);
// Reads a PNG (any channel count, expanded to RGBA); throws InputError naming the file.
Image readPng(const std::filesystem::path& file);

// OpenEXR bytes of a width × height RGBA float texture (row 0 at the top, PIZ, one thread, so
// the same texels give the same bytes), as HALF channels or FLOAT. A value that is a half
// already keeps its exact bits as HALF.
std::vector<std::byte> encodeExr(std::span<const float> rgba, int width, int height, bool half);

}  // namespace dawnforge::exporters
