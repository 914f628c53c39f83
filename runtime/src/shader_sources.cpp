#include "shader_sources.hpp"

#include <dawnforge/core/format.hpp>

#include <set>
#include <stdexcept>

namespace dawnforge::runtime::detail {

namespace {

std::string_view find(std::string_view name) {
    for (std::size_t i = 0; i < kShaderCount; ++i)
        if (kShaders[i].name == name) return kShaders[i].source;
    throw std::logic_error(format("no embedded shader named {}", name));
}

void expand(std::string_view name, std::string& out, std::set<std::string_view>& included) {
    const std::string_view text = find(name);
    std::size_t start = 0;
    while (start < text.size()) {
        std::size_t end = text.find('\n', start);
        if (end == std::string_view::npos) end = text.size();
        const std::string_view line = text.substr(start, end - start);
        if (line.starts_with("#include \"")) {
            const std::size_t close = line.find('"', 10);
            const std::string_view file = line.substr(10, close - 10);
            if (included.insert(file).second) expand(file, out, included);
        } else {
            out.append(line);
            out.push_back('\n');
        }
        start = end + 1;
    }
}

}  // namespace

std::string shaderSource(std::string_view name, const std::vector<std::string>& defines) {
    std::string body;
    std::set<std::string_view> included;
    expand(name, body, included);
    // The #version line stays first; defines follow it.
    const std::size_t versionEnd = body.starts_with("#version") ? body.find('\n') + 1 : 0;
    std::string prelude;
    for (const std::string& d : defines) prelude += "#define " + d + "\n";
    return body.substr(0, versionEnd) + prelude + body.substr(versionEnd);
}

}  // namespace dawnforge::runtime::detail
