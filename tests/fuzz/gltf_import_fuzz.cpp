// libFuzzer target: glTF and GLB import (docs/STYLE.md 10). Any input loads as a usable mesh or
// is refused with a one-line InputError; nothing else may happen (tests/fuzz/import_fuzz.hpp).
// The reader tells GLB from glTF text by the magic "glTF", so one target covers both.
// Seed it with files the exporters write, e.g.
//   cmake -B build-fuzz -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_C_COMPILER=clang -DDAWNFORGE_BUILD_FUZZERS=ON
//   cmake --build build-fuzz --target gltf_import_fuzz example_02_write_scene
//   mkdir -p corpus && build-fuzz/bin/example_02_write_scene corpus/scene.glb
//   build-fuzz/bin/gltf_import_fuzz corpus/
#include "import_fuzz.hpp"

#include <cstring>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const bool binary = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
    dawnforge::fuzz::loadOrRefuse(data, size, binary ? ".glb" : ".gltf");
    return 0;
}
