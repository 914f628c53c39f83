#pragma once
// Shared by the libFuzzer targets for mesh import (obj_import_fuzz, gltf_import_fuzz).
#include <cstddef>
#include <cstdint>

namespace dawnforge::fuzz {

// Writes the input to a file named fuzz<extension> in a temporary folder of this process
// (import reads files only) and loads it. The property (as in tests/core/import_fuzz_test.cpp):
// a mesh that loads has indices in range, finite positions and attributes of the right
// length; anything else is an InputError with a one-line message. The reader runs in a child
// process, as for any user's file: its crash or hang there aborts too. A violation aborts;
// any other exception escapes, which libFuzzer reports too.
void loadOrRefuse(const std::uint8_t* data, std::size_t size, const char* extension);

}  // namespace dawnforge::fuzz
