#pragma once
// OFF import through CGAL's reader (OFF is CGAL's own format: its reader takes every
// variant in CGAL's data, comments anywhere and colours of three components, which
// Assimp 5.2 refuses). Private to core: no CGAL type leaves import_off.cpp.
#include <glm/vec3.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace dawnforge::detail {

struct Polygons {
    std::vector<glm::dvec3> points;
    std::vector<std::vector<std::uint32_t>> faces;  // corner indices into points, in order
};

// The points and faces of an OFF file. Throws InputError naming `name` (the file as the
// user gave it) when the file cannot be read (a face using a point the file does not
// have, too), or its header claims more than the file can hold.
Polygons readOff(const std::filesystem::path& file, const std::string& name);

}  // namespace dawnforge::detail
