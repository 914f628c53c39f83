#pragma once
// Third-party readers run on a user's file in a child process (ARCHITECTURE.md 4.10): a
// crash, a hang or a heap corruption inside Assimp, tinygltf, OpenEXR or stb ends that
// child, and the command reports one line naming the file and exits 2. The child has
// limits on wall time, processor time and memory, writes no file, opens nothing for
// writing, starts no program and makes no network connection (seccomp), and hands its
// result back over a pipe as bytes that the caller checks before trusting them.
#include <dawnforge/core/error.hpp>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>

namespace dawnforge {

struct ReaderLimits {
    double seconds = 60.0;    // wall-clock time of one reading; processor time is capped at the same
    double gigabytes = 8.0;   // address space the reader may add to what the fork brought
};

// The limits of this process's readers: defaults until the CLI's --read-timeout and
// --read-memory set them, once, before any command runs.
ReaderLimits readerLimits();
void setReaderLimits(const ReaderLimits& limits);

// A reader that did not give an answer: it crashed, ran out of time or memory. The message
// names the file and what happened; the CLI reports it as any InputError (exit 2).
class ReaderFailure : public InputError {
public:
    enum class Kind { Crashed, TimedOut, OutOfMemory, NoAnswer };
    ReaderFailure(Kind kind, const std::string& message) : InputError(message), kind_(kind) {}
    Kind kind() const { return kind_; }

private:
    Kind kind_;
};

// The child's answer goes straight into the pipe, and the parent reads it straight into its
// own arrays: a mesh of 50 MB is copied once on each side, not assembled in buffers first.
class AnswerSink {
public:
    virtual void write(const void* data, std::size_t size) = 0;

protected:
    ~AnswerSink() = default;
};
class AnswerSource {
public:
    // Fills `data`; throws InputError if that is more than the child announced.
    virtual void read(void* data, std::size_t size) = 0;
    virtual std::uint64_t left() const = 0;  // of the bytes the child announced

protected:
    ~AnswerSource() = default;
};

// What the child's reader found: its size in bytes, and how to write them.
struct Answer {
    std::uint64_t size = 0;
    std::function<void(AnswerSink&)> write;
};

// Runs `produce` in a child process under readerLimits() and gives its answer to `consume`
// in this one, which must read exactly `size` bytes and check them before trusting them.
// `reader` names the reader in messages ("FBX" gives "FILE: the FBX reader crashed (signal 11,
// SIGSEGV)"). An InputError (or another exception) thrown by `produce` is thrown here with the
// same message, as an InputError. Call it from a thread that holds no lock `produce` needs:
// the child is a fork of this process.
void readIsolated(const std::filesystem::path& file, std::string_view reader, const std::function<Answer()>& produce,
                  const std::function<void(AnswerSource&)>& consume);

}  // namespace dawnforge
