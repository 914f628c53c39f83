// OpenEXR output (the only OpenEXR writer; vat_read.cpp reads).
#include <dawnforge/exporters/image.hpp>

#include <dawnforge/core/error.hpp>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <ImfStdIO.h>
#include <Imath/half.h>

#include <cstring>
#include <string>

namespace dawnforge::exporters {

std::vector<std::byte> encodeExr(std::span<const float> rgba, int width, int height, bool half) {
    DAWNFORGE_ASSERT(width > 0 && height > 0 && rgba.size() == std::size_t(width) * std::size_t(height) * 4,
                     "texture size and texel count disagree");
    Imf::Header header(width, height);
    header.compression() = Imf::PIZ_COMPRESSION;
    header.lineOrder() = Imf::INCREASING_Y;  // row 0 is the top of the image
    const Imf::PixelType type = half ? Imf::HALF : Imf::FLOAT;
    const char* names[4] = {"R", "G", "B", "A"};
    for (const char* c : names) header.channels().insert(c, Imf::Channel(type));
    std::vector<Imath::half> halves;
    if (half) {
        halves.resize(rgba.size());
        for (std::size_t i = 0; i < rgba.size(); ++i) halves[i] = Imath::half(rgba[i]);
    }
    Imf::FrameBuffer frame;
    const std::size_t element = half ? sizeof(Imath::half) : sizeof(float);
    char* base = half ? reinterpret_cast<char*>(halves.data()) : const_cast<char*>(reinterpret_cast<const char*>(rgba.data()));
    for (int c = 0; c < 4; ++c)
        frame.insert(names[c], Imf::Slice(type, base + std::size_t(c) * element, 4 * element, 4 * element * std::size_t(width)));
    Imf::StdOSStream out;
    {
        Imf::OutputFile file(out, header, 1);  // one thread: the bytes do not depend on a pool
        file.setFrameBuffer(frame);
        file.writePixels(height);
    }
    const std::string bytes = out.str();
    std::vector<std::byte> result(bytes.size());
    std::memcpy(result.data(), bytes.data(), bytes.size());
    return result;
}

}  // namespace dawnforge::exporters
