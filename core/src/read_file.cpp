#include <dawnforge/core/read_file.hpp>

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>

#include <cstring>
#include <fstream>
#include <sstream>

namespace dawnforge {

std::string readTextFile(const std::filesystem::path& file) {
    std::error_code ec;
    if (!std::filesystem::exists(file, ec)) throw InputError(format("{}: no such file", file.string()));
    std::ifstream in(file, std::ios::binary);
    std::ostringstream text;
    if (in && !std::filesystem::is_directory(file, ec)) text << in.rdbuf();
    if (!in || in.bad() || std::filesystem::is_directory(file, ec))
        throw InputError(format("{}: cannot be read", file.string()));
    return std::move(text).str();
}

std::vector<std::byte> readBinaryFile(const std::filesystem::path& file) {
    const std::string text = readTextFile(file);
    std::vector<std::byte> bytes(text.size());
    std::memcpy(bytes.data(), text.data(), text.size());
    return bytes;
}

}  // namespace dawnforge
