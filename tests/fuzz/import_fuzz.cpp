#include "import_fuzz.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/import.hpp>
#include <dawnforge/core/isolate.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <unistd.h>

namespace dawnforge::fuzz {
namespace {

void check(bool ok, const char* what) {
    if (ok) return;
    std::fprintf(stderr, "import fuzz: %s\n", what);
    std::abort();
}

void checkMesh(const Mesh& m) {
    const std::size_t n = m.positions.size();
    check(!m.indices.empty() && m.indices.size() % 3 == 0, "a loaded mesh has no whole triangles");
    for (std::uint32_t i : m.indices) check(i < n, "an index is out of range");
    for (const glm::vec3& p : m.positions)
        check(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z), "a position is not finite");
    for (std::size_t size : {m.normals.size(), m.uv0.size(), m.uv1.size(), m.uv2.size(), m.uv3.size(),
                             m.materialIds.size(), m.pieceIds.size()})
        check(size == 0 || size == n, "an attribute's length differs from the vertex count");
}

// One folder per process, removed at exit.
const std::filesystem::path& folder() {
    static const std::filesystem::path dir = [] {
        std::string pattern = (std::filesystem::temp_directory_path() / "dawnforge-fuzz-XXXXXX").string();
        check(::mkdtemp(pattern.data()) != nullptr, "mkdtemp failed");
        std::atexit([] { std::filesystem::remove_all(folder()); });
        return std::filesystem::path(pattern);
    }();
    return dir;
}

}  // namespace

void loadOrRefuse(const std::uint8_t* data, std::size_t size, const char* extension) {
    const std::filesystem::path file = folder() / (std::string("fuzz") + extension);
    std::filesystem::remove(file);  // a new file: overwriting one in place makes ext4 flush it on close
    std::ofstream(file, std::ios::binary).write(reinterpret_cast<const char*>(data), std::streamsize(size));
    try {
        checkMesh(loadMesh(file));
        if (std::string_view(extension) != ".obj")
            for (const MeshNode& node : loadMeshNodes(file)) checkMesh(node.mesh);
    } catch (const ReaderFailure& e) {
        // The reader ran in a child (core/isolate.hpp), which kept this process alive; the
        // input is still a finding: the reader crashed, hung or ran out of memory on it.
        std::fprintf(stderr, "import fuzz: %s\n", e.what());
        std::abort();
    } catch (const InputError& e) {
        check(std::string_view(e.what()).find('\n') == std::string_view::npos, "an InputError has several lines");
    }
}

}  // namespace dawnforge::fuzz
