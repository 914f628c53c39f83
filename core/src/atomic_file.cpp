#include <dawnforge/core/atomic_file.hpp>
#include <dawnforge/core/error.hpp>

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <dawnforge/core/format.hpp>

namespace dawnforge {

namespace fs = std::filesystem;

namespace {

fs::path temporaryNameFor(const fs::path& target) {
    static std::atomic<unsigned> counter{0};
    fs::path tmp = target;
    tmp += format(".tmp-{}-{}", ::getpid(), counter++);
    return tmp;
}

}  // namespace

AtomicFile::AtomicFile(fs::path target) : target_(std::move(target)), temporary_(temporaryNameFor(target_)) {
    std::error_code ec;
    if (fs::is_directory(target_, ec))
        throw InputError(format("{}: cannot write the file: a folder has that name", target_.string()));
    out_.open(temporary_, std::ios::binary | std::ios::trunc);
    if (!out_)
        throw InputError(format("{}: cannot write the file: {}", target_.string(), std::strerror(errno)));
}

AtomicFile::~AtomicFile() {
    if (committed_) return;
    out_.close();
    std::error_code ec;
    fs::remove(temporary_, ec);
}

void AtomicFile::commit() {
    DAWNFORGE_ASSERT(!committed_, "committed twice");
    out_.flush();
    const bool good = out_.good();
    out_.close();
    std::error_code ec;
    if (!good || out_.fail()) {
        fs::remove(temporary_, ec);
        throw InputError(format("{}: writing the file failed (disk full?)", target_.string()));
    }
    fs::rename(temporary_, target_, ec);
    if (ec) {
        fs::remove(temporary_, ec);
        throw InputError(format("{}: cannot write the file: {}", target_.string(), ec.message()));
    }
    committed_ = true;
}

void writeFileAtomically(const fs::path& target, std::span<const std::byte> bytes) {
    AtomicFile file(target);
    file.stream().write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    file.commit();
}

void writeFileAtomically(const fs::path& target, std::string_view text) {
    writeFileAtomically(target, std::as_bytes(std::span(text.data(), text.size())));
}

void ensureOutputDirectory(const fs::path& dir) {
    std::error_code ec;
    if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
        throw InputError(format("{}: cannot use it as the output folder: it is a file", dir.string()));
    fs::create_directories(dir, ec);
    if (ec) throw InputError(format("{}: cannot create the output folder: {}", dir.string(), ec.message()));
}

}  // namespace dawnforge
