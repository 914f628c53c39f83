#pragma once
// Helpers shared by the test executables: temporary folders, OBJ fixtures, running the
// dawnforge executable and the Khronos glTF-Validator.
#include <dawnforge/core/error.hpp>
#include <dawnforge/core/isolate.hpp>
#include <dawnforge/core/mesh.hpp>
#include <dawnforge/core/seed.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace dawnforge::test {

// A fresh folder under the system temp folder, removed with its contents at scope end.
class TempDir {
public:
    TempDir();
    ~TempDir();
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    const std::filesystem::path& path() const { return path_; }
    std::filesystem::path operator/(const std::string& name) const { return path_ / name; }
    std::vector<std::string> entries() const;  // file names in the folder, sorted

private:
    std::filesystem::path path_;
};

std::filesystem::path dataFile(const std::string& name);  // tests/data/<name>

// One piece of damage to a file's bytes, as a fuzzer would do it: a cut, flipped bytes, a run
// duplicated, deleted or spliced from `donor`, or a number (a digit run, or four bytes of a
// binary file) made huge.
void damage(std::string& bytes, const std::string& donor, Rng& rng);

// Sets the process's reader limits (core/isolate.hpp) until the end of the scope.
class ScopedReaderLimits {
public:
    explicit ScopedReaderLimits(const ReaderLimits& limits) : saved_(readerLimits()) { setReaderLimits(limits); }
    ~ScopedReaderLimits() { setReaderLimits(saved_); }
    ScopedReaderLimits(const ScopedReaderLimits&) = delete;
    ScopedReaderLimits& operator=(const ScopedReaderLimits&) = delete;

private:
    ReaderLimits saved_;
};
std::string readText(const std::filesystem::path& file);
std::vector<unsigned char> readBytes(const std::filesystem::path& file);
void writeText(const std::filesystem::path& file, const std::string& text);

// Writes positions and triangles as an OBJ file (%.9g: floats round-trip exactly).
void writeObj(const std::filesystem::path& file, const Mesh& mesh);

struct RunResult {
    int exitCode = -1;
    std::string out;
    std::string err;
};
// Runs `program args...` with stdin closed and captures its output.
RunResult run(const std::string& program, const std::vector<std::string>& args);
// Runs the dawnforge executable under test.
RunResult runDawnforge(const std::vector<std::string>& args);
// The world the streaming tests draw: 2 × 2 tiles of 128 m (seed 5) with a quick bake and one
// HLOD node, made by `dawnforge world plan` and `world build` once per build tree (in
// DAWNFORGE_TEST_WORK, under a lock: a second test process waits, then finds it built).
const std::filesystem::path& streamWorld();

// Runs the Khronos glTF-Validator (tools/gltf-validator) over one file and expects no
// error. Without node or the validator's npm package, the check is skipped: the test is
// reported as skipped with the reason, unless one of its other checks fails.
void expectValidGltf(const std::filesystem::path& file);

// Lines in a text (a trailing newline does not start another line).
std::size_t lineCount(const std::string& text);

// The message of the InputError that f() throws, or "no InputError".
std::string inputErrorOf(auto&& f) {
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    }
    return "no InputError";
}
inline bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Signed volume of a closed mesh by the divergence theorem, in long double: an
// independent reference for the CGAL-based inspection.
double referenceVolume(const Mesh& mesh);

// A closed torus around the Y axis (outward, counter-clockwise): non-convex, genus 1.
Mesh makeTorus(float majorRadius, float minorRadius, int around, int section);

// A closed box from -1 to 1 whose faces are n × n squares of two triangles (outward): vertices
// and edges on the planes x, y, z = -1 + 2k/n.
Mesh gridBox(int n);

// Generalised winding number of a closed mesh at p (1 inside, 0 outside; van Oosterom
// and Strackee's solid angle): an inside test that needs no library.
double windingNumber(const Mesh& mesh, const glm::dvec3& p);

}  // namespace dawnforge::test
