// libFuzzer target: recipe parsing (docs/STYLE.md 10). Any input either parses or throws an
// InputError whose message is one line; nothing else may happen.
//   cmake -B build-fuzz -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_C_COMPILER=clang -DDAWNFORGE_BUILD_FUZZERS=ON
//   cmake --build build-fuzz --target recipe_fuzz && build-fuzz/bin/recipe_fuzz examples/recipes/
#include <dawnforge/core/error.hpp>
#include <dawnforge/procgen/recipe.hpp>

#include <cstdint>
#include <cstdlib>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        dawnforge::procgen::parseRecipe(text, "fuzz.json");
    } catch (const dawnforge::InputError& e) {
        if (std::string_view(e.what()).find('\n') != std::string_view::npos) std::abort();
    }
    return 0;
}
