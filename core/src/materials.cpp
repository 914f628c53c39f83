#include <dawnforge/core/materials.hpp>

#include <dawnforge/core/error.hpp>

namespace dawnforge {

const char* materialName(std::uint8_t id) {
    static const char* const kNames[kMaterialCount] = {
        "asphalt", "paving", "brick", "concrete", "plaster", "glass", "metal", "trim",
        "roof_tiles", "roof_flat", "wood", "interior_wall", "floor", "ground", "sand", "rubble"};
    DAWNFORGE_ASSERT(id < kMaterialCount, "material id above 15");
    return kNames[id];
}

}  // namespace dawnforge
