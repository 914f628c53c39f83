// Fuzzing the readers with damaged real files (issue: untrusted files): Assimp's own test
// models (Debian assimp-testmodels: OBJ, glTF, GLB, FBX, STL, PLY, OFF) and CGAL's meshes
// (Debian libcgal-demo), with bytes flipped, runs cut, duplicated or spliced from another
// file, and numbers made huge. Each damaged file is read through loadMesh, whose reader runs
// in a child process: it loads as a mesh that is safe to use, or is refused with one line.
// The parent never crashes or hangs; the readers' own crashes and hangs, which isolation
// turns into refusals, are counted and printed. The sweep is fixed (seeded); the Release pass
// reads 3,000 files, the sanitizer pass 300.
#include "test_support.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/import.hpp>
#include <dawnforge/core/isolate.hpp>
#include <dawnforge/core/seed.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <map>

namespace dawnforge {
namespace {

namespace fs = std::filesystem;
using test::TempDir;

constexpr std::uintmax_t kMaxSeedBytes = 64 * 1024;  // small files: many cases, each quick

// The real files the damage starts from, sorted: Assimp's test models of the formats a
// studio exports, and a few of CGAL's meshes unpacked into `work`.
std::vector<fs::path> seedFiles(const fs::path& work) {
    std::vector<fs::path> seeds;
    const fs::path models = "/usr/share/assimp/models";
    for (const char* folder : {"OBJ", "glTF2", "FBX", "STL", "PLY", "OFF"}) {
        std::error_code ec;
        for (auto it = fs::recursive_directory_iterator(models / folder, ec); !ec && it != fs::end(it); it.increment(ec)) {
            std::string ext = it->path().extension().string();
            std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
            const bool mesh = ext == ".obj" || ext == ".gltf" || ext == ".glb" || ext == ".fbx" || ext == ".stl" ||
                              ext == ".ply" || ext == ".off";
            if (mesh && it->is_regular_file() && it->file_size() <= kMaxSeedBytes) seeds.push_back(it->path());
        }
    }
    const std::string cgal = "/usr/share/doc/libcgal-dev/data.tar.gz";
    const std::vector<std::string> meshes = {"cube.off", "tetrahedron.off", "cross.off", "elephant.off", "hand.off"};
    std::string command = "tar xzf " + cgal + " -C '" + work.string() + "'";
    for (const std::string& m : meshes) command += " data/meshes/" + m;
    if (fs::exists(cgal) && std::system((command + " 2>/dev/null").c_str()) == 0)
        for (const std::string& m : meshes)
            if (fs::exists(work / "data/meshes" / m)) seeds.push_back(work / "data/meshes" / m);
    std::sort(seeds.begin(), seeds.end());
    return seeds;
}

// The property of a mesh that loaded, checked without validateMeshData.
bool usable(const Mesh& m) {
    const std::size_t n = m.positions.size();
    if (m.indices.empty() || m.indices.size() % 3 != 0) return false;
    if (std::any_of(m.indices.begin(), m.indices.end(), [n](std::uint32_t i) { return i >= n; })) return false;
    for (const glm::vec3& p : m.positions)
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return false;
    for (std::size_t size : {m.normals.size(), m.uv0.size(), m.materialIds.size(), m.pieceIds.size()})
        if (size != 0 && size != n) return false;
    return true;
}

// Copies the files beside `seed` (a glTF's buffers, an OBJ's materials) into `dir`.
void copySiblings(const fs::path& seed, const fs::path& dir) {
    fs::create_directories(dir);
    for (const fs::directory_entry& e : fs::directory_iterator(seed.parent_path()))
        if (e.is_regular_file() && e.path() != seed && e.file_size() < 4 * 1024 * 1024)
            fs::copy_file(e.path(), dir / e.path().filename(), fs::copy_options::overwrite_existing);
}

TEST(ImportFuzz, DamagedRealFilesOfEveryFormatLoadSafelyOrAreRefused) {
    TempDir work;
    const std::vector<fs::path> seeds = seedFiles(work.path());
    if (seeds.size() < 20) GTEST_SKIP() << "assimp-testmodels and libcgal-demo are not installed (./run installs them)";
    // Good seeds parse in milliseconds (tens under the sanitizers): a reader still busy after
    // 1 s (3 s) is hanging.
    const test::ScopedReaderLimits limits({.seconds = DAWNFORGE_SANITIZED ? 3.0 : 1.0, .gigabytes = 2.0});
    const int cases = DAWNFORGE_SANITIZED ? 300 : 3000;
    Rng rng(deriveSeed(4, "import-fuzz-real"));
    std::map<std::string, int> outcomes;
    std::vector<std::string> donors;
    for (const fs::path& seed : seeds) donors.push_back(test::readText(seed));
    const auto start = std::chrono::steady_clock::now();
    for (int i = 0; i < cases; ++i) {
        const std::size_t k = std::size_t(i) % seeds.size();
        const fs::path dir = work / ("case" + std::to_string(k)), file = dir / seeds[k].filename();
        if (!fs::exists(dir)) copySiblings(seeds[k], dir);
        std::string bytes = donors[k];
        for (int d = rng.range(1, 3); d > 0; --d) test::damage(bytes, donors[rng.below(donors.size())], rng);
        fs::remove(file);
        test::writeText(file, bytes);
        const std::string what = "case " + std::to_string(i) + " (" + seeds[k].string() + ")";
        try {
            ASSERT_TRUE(usable(loadMesh(file))) << what;
            ++outcomes["loaded"];
        } catch (const ReaderFailure& e) {
            const std::string kinds[] = {"reader crashed", "reader timed out", "reader out of memory", "reader gave no answer"};
            ++outcomes[kinds[int(e.kind())]];
            ++outcomes[kinds[int(e.kind())] + (" (" + seeds[k].extension().string() + ")")];
            ASSERT_EQ(std::string(e.what()).find('\n'), std::string::npos) << what;
        } catch (const InputError& e) {
            ++outcomes["refused"];
            ASSERT_EQ(std::string(e.what()).find('\n'), std::string::npos) << what << ": " << e.what();
        } catch (const std::exception& e) {
            FAIL() << what << ": not an InputError: " << e.what();
        }
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::string summary;
    for (const auto& [outcome, count] : outcomes) summary += " " + outcome + " " + std::to_string(count) + ";";
    std::printf("%d damaged files from %zu real ones:%s %.1f ms a file\n", cases, seeds.size(), summary.c_str(),
                1000.0 * seconds / cases);
    EXPECT_GT(outcomes["refused"], cases / 4);  // most damage is caught by the readers or our checks...
    EXPECT_GT(outcomes["loaded"], cases / 20);  // ...and some is harmless
}

}  // namespace
}  // namespace dawnforge
