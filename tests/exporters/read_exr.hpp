#pragma once
// The exporters' EXR files read back for their tests, with OpenEXR alone (none of the
// writer's code): every channel's type and the file's layout, and RGBA as float slices.
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <glm/vec4.hpp>

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace dawnforge::test {

struct Exr {
    int width = 0, height = 0;
    Imath::V2i origin{0, 0};
    std::vector<std::pair<std::string, Imf::PixelType>> channels;
    Imf::Compression compression = Imf::NO_COMPRESSION;
    Imf::LineOrder lineOrder = Imf::INCREASING_Y;
    std::vector<float> rgba;  // row 0 = the first row in the file (the top)

    glm::vec4 texel(int rowFromTop, int column) const {
        const float* p = rgba.data() + (std::size_t(rowFromTop) * std::size_t(width) + std::size_t(column)) * 4;
        return {p[0], p[1], p[2], p[3]};
    }
};

// Float slices: OpenEXR converts half to float exactly (the RGBA API would round to half).
inline Exr readExr(const std::filesystem::path& file) {
    Imf::InputFile in(file.c_str());
    const Imf::Header& header = in.header();
    Exr exr;
    const Imath::Box2i window = header.dataWindow();
    exr.origin = window.min;
    exr.width = window.max.x - window.min.x + 1;
    exr.height = window.max.y - window.min.y + 1;
    for (auto c = header.channels().begin(); c != header.channels().end(); ++c)
        exr.channels.emplace_back(c.name(), c.channel().type);
    exr.compression = header.compression();
    exr.lineOrder = header.lineOrder();
    if (window.min != Imath::V2i(0, 0)) return exr;  // the caller's origin check fails
    exr.rgba.assign(std::size_t(exr.width) * std::size_t(exr.height) * 4, -1.0f);
    Imf::FrameBuffer frame;
    const char* names[4] = {"R", "G", "B", "A"};
    for (int c = 0; c < 4; ++c)
        frame.insert(names[c], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(exr.rgba.data() + c), 4 * sizeof(float),
                                          4 * sizeof(float) * std::size_t(exr.width)));
    in.setFrameBuffer(frame);
    in.readPixels(window.min.y, window.max.y);
    return exr;
}

}  // namespace dawnforge::test
