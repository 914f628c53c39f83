#pragma once
// The shader files under runtime/shaders/, embedded at build time (cmake/EmbedShaders.cmake).
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace dawnforge::runtime::detail {

struct EmbeddedShader {
    std::string_view name;
    std::string_view source;
};
extern const EmbeddedShader kShaders[];
extern const std::size_t kShaderCount;

// The source of `name` with `#include "file.glsl"` lines replaced by those files (once
// each), and `defines` (e.g. "SHADOW_PASS") inserted after the #version line.
std::string shaderSource(std::string_view name, const std::vector<std::string>& defines = {});

}  // namespace dawnforge::runtime::detail
