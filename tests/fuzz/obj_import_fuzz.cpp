// libFuzzer target: OBJ import (docs/STYLE.md 10). Any input loads as a usable mesh or is
// refused with a one-line InputError; nothing else may happen (tests/fuzz/import_fuzz.hpp).
//   cmake -B build-fuzz -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_C_COMPILER=clang -DDAWNFORGE_BUILD_FUZZERS=ON
//   cmake --build build-fuzz --target obj_import_fuzz && build-fuzz/bin/obj_import_fuzz tests/data/
#include "import_fuzz.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    dawnforge::fuzz::loadOrRefuse(data, size, ".obj");
    return 0;
}
