#pragma once
// Atomic file output: write to a temporary name in the same folder, then rename, so
// that no output file is ever left half-written.
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <span>
#include <string_view>

namespace dawnforge {

class AtomicFile {
public:
    explicit AtomicFile(std::filesystem::path target);  // throws InputError if it cannot be created
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;
    ~AtomicFile();  // removes the temporary file unless commit() succeeded

    std::ostream& stream() { return out_; }
    void commit();  // flushes, closes and renames onto the target; throws InputError on failure

private:
    std::filesystem::path target_;
    std::filesystem::path temporary_;
    std::ofstream out_;
    bool committed_ = false;
};

void writeFileAtomically(const std::filesystem::path& target, std::span<const std::byte> bytes);
void writeFileAtomically(const std::filesystem::path& target, std::string_view text);

// Creates `dir` (and parents) for output; throws InputError if it exists as a file or
// cannot be created.
void ensureOutputDirectory(const std::filesystem::path& dir);

}  // namespace dawnforge
