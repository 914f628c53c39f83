// A reader in a child process (isolate.hpp). The child is a fork of the caller: it sets its
// limits, drops what it does not need, runs the reader and writes one record to a pipe: 'O',
// the answer's size (8 bytes) and the answer, or 'E', a size and an error message. The parent
// reads the record until the wall-time limit; when it is cut short, the child's exit status
// says what happened.
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/isolate.hpp>

#include <fcntl.h>
#include <linux/audit.h>
#include <linux/filter.h>
#include <linux/seccomp.h>
#include <poll.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <new>
#include <vector>

namespace dawnforge {

namespace {

constexpr int kOutOfMemoryExit = 86;  // the child's exit code when an allocation failed
constexpr int kOutOfMemoryStatus = kOutOfMemoryExit << 8;  // as waitpid reports that exit

std::mutex& limitsMutex() {
    static std::mutex m;
    return m;
}

ReaderLimits& processLimits() {
    static ReaderLimits limits;
    return limits;
}

// ---------------------------------------------------------------- the child

// Everything the child writes goes through this: no allocation, retries on EINTR.
bool writeAll(int fd, const char* data, std::size_t size) {
    while (size > 0) {
        const ssize_t n = ::write(fd, data, size);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        data += n;
        size -= std::size_t(n);
    }
    return true;
}

// A seccomp filter: no network, no new program, no tracing, no file opened for writing,
// created, removed or renamed. Each refused call fails with EPERM (a reader that tries gets
// an error it already handles). Returns false where the architecture is not known here.
bool denyEscapes() {
#if defined(__x86_64__)
    constexpr std::uint32_t kArch = AUDIT_ARCH_X86_64;
#elif defined(__aarch64__)
    constexpr std::uint32_t kArch = AUDIT_ARCH_AARCH64;
#else
    return false;
#endif
    constexpr std::uint32_t kDeny = SECCOMP_RET_ERRNO | (EPERM & SECCOMP_RET_DATA);
    constexpr std::uint32_t kWriteFlags = O_WRONLY | O_RDWR | O_CREAT | O_TRUNC | O_APPEND;
    const std::uint32_t kArgs = offsetof(seccomp_data, args);
    std::vector<sock_filter> f{
        BPF_STMT(BPF_LD | BPF_W | BPF_ABS, offsetof(seccomp_data, arch)),
        BPF_JUMP(BPF_JMP | BPF_JEQ | BPF_K, kArch, 1, 0),
        BPF_STMT(BPF_RET | BPF_K, SECCOMP_RET_KILL_PROCESS),
        BPF_STMT(BPF_LD | BPF_W | BPF_ABS, offsetof(seccomp_data, nr)),
    };
    std::vector<long> refused{SYS_socket,   SYS_socketpair, SYS_connect,  SYS_bind,   SYS_listen,
                              SYS_accept,   SYS_accept4,    SYS_execve,   SYS_execveat, SYS_ptrace,
                              SYS_process_vm_writev,        SYS_unlinkat, SYS_renameat, SYS_renameat2,
                              SYS_mkdirat,  SYS_linkat,     SYS_symlinkat, SYS_truncate, SYS_fchmodat,
                              SYS_fchownat};
#ifdef SYS_openat2
    refused.push_back(SYS_openat2);  // its flags are behind a pointer: refused whole (glibc falls back)
#endif
#ifdef SYS_open  // the older calls that x86-64 still has and AArch64 does not
    refused.insert(refused.end(), {SYS_creat, SYS_unlink, SYS_rename, SYS_mkdir, SYS_rmdir, SYS_link, SYS_symlink,
                                   SYS_chmod, SYS_chown});
#endif
    for (const long nr : refused) {
        f.push_back(BPF_JUMP(BPF_JMP | BPF_JEQ | BPF_K, std::uint32_t(nr), 0, 1));
        f.push_back(BPF_STMT(BPF_RET | BPF_K, kDeny));
    }
    // open(path, flags) and openat(dir, path, flags): refused when the flags would write.
    auto refuseWritingOpen = [&](long nr, std::uint32_t flagsArg) {
        f.push_back(BPF_JUMP(BPF_JMP | BPF_JEQ | BPF_K, std::uint32_t(nr), 0, 4));
        f.push_back(BPF_STMT(BPF_LD | BPF_W | BPF_ABS, kArgs + 8 * flagsArg));  // the low half (little-endian)
        f.push_back(BPF_JUMP(BPF_JMP | BPF_JSET | BPF_K, kWriteFlags, 0, 1));
        f.push_back(BPF_STMT(BPF_RET | BPF_K, kDeny));
        f.push_back(BPF_STMT(BPF_RET | BPF_K, SECCOMP_RET_ALLOW));
    };
    refuseWritingOpen(SYS_openat, 2);
#ifdef SYS_open
    refuseWritingOpen(SYS_open, 1);
#endif
    f.push_back(BPF_STMT(BPF_RET | BPF_K, SECCOMP_RET_ALLOW));
    const sock_fprog program{static_cast<unsigned short>(f.size()), f.data()};
    return ::prctl(PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0) == 0 &&
           ::syscall(SYS_seccomp, SECCOMP_SET_MODE_FILTER, 0, &program) == 0;
}

void setLimit(int resource, rlim_t value) {
    const rlimit limit{value, value};
    ::setrlimit(resource, &limit);
}

// This process's address space now (/proc/self/statm's first field), 0 if unknown.
double addressSpaceBytes() {
    char text[128] = {};
    const int fd = ::open("/proc/self/statm", O_RDONLY | O_CLOEXEC);
    if (fd < 0) return 0.0;
    const ssize_t n = ::read(fd, text, sizeof text - 1);
    ::close(fd);
    return n > 0 ? std::strtod(text, nullptr) * double(::sysconf(_SC_PAGESIZE)) : 0.0;
}

// The child's set-up before it reads: its own process group (so the parent can end
// whatever it leaves), limits, quiet standard streams (a library's complaints and glibc's
// heap reports would otherwise reach the user), only the pipe among the descriptors.
void enterChild(int pipeFd, const ReaderLimits& limits) {
    ::setpgid(0, 0);
    ::signal(SIGPIPE, SIG_IGN);
    setLimit(RLIMIT_CORE, 0);
    setLimit(RLIMIT_FSIZE, 0);
    setLimit(RLIMIT_CPU, rlim_t(std::ceil(limits.seconds)) + 1);
    // On top of what the fork brought along: the parent's libraries, stacks and heap, and in a
    // sanitizer build the terabytes its shadow and allocator reserved at start-up (memory mapped
    // later inside a reservation does not count again).
    setLimit(RLIMIT_AS, rlim_t(addressSpaceBytes() + limits.gigabytes * double(1ull << 30)));
    // The pipe moves to 3 first: a parent started with stdin closed may have it at 0.
    if (pipeFd != 3) ::dup2(pipeFd, 3);
    if (const int null = ::open("/dev/null", O_RDWR | O_CLOEXEC); null >= 0) {
        ::dup2(null, STDIN_FILENO);
        ::dup2(null, STDOUT_FILENO);
#if !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)
        ::dup2(null, STDERR_FILENO);  // a sanitizer's report is kept: the tests read it
#endif
    }
    ::close_range(4, ~0u, 0);
    std::set_new_handler([] { ::_exit(kOutOfMemoryExit); });
    denyEscapes();
}

constexpr std::size_t kPipeBuffer = 1 << 20;  // a mesh answer is many small values between large arrays

// Buffered: one write a megabyte, not one per value (a city's thousands of nodes would cost
// hundreds of thousands of system calls and a pipe lock contended with the reader).
class PipeSink final : public AnswerSink {
public:
    PipeSink() { buffer_.reserve(kPipeBuffer); }
    void write(const void* data, std::size_t size) override {
        if (buffer_.size() + size > kPipeBuffer) flush();
        if (size >= kPipeBuffer) return put(static_cast<const char*>(data), size);
        buffer_.insert(buffer_.end(), static_cast<const char*>(data), static_cast<const char*>(data) + size);
    }
    void flush() {
        put(buffer_.data(), buffer_.size());
        buffer_.clear();
    }

private:
    static void put(const char* data, std::size_t size) {
        if (!writeAll(3, data, size)) ::_exit(1);  // the parent is gone
    }
    std::vector<char> buffer_;
};

// Writes one record: its kind, its size, its bytes.
void writeRecord(PipeSink& sink, char kind, std::uint64_t size, const std::function<void(AnswerSink&)>& write) {
    sink.write(&kind, 1);
    sink.write(&size, sizeof size);
    write(sink);
    sink.flush();
}

[[noreturn]] void runChild(int pipeFd, const ReaderLimits& limits, const std::function<Answer()>& produce) {
    enterChild(pipeFd, limits);
    PipeSink sink;
    std::string error;
    try {
        const Answer answer = produce();
        writeRecord(sink, 'O', answer.size, answer.write);
        ::_exit(0);
    } catch (const std::bad_alloc&) {
        ::_exit(kOutOfMemoryExit);
    } catch (const std::exception& e) {
        error = e.what();
    } catch (...) {
        error = "the reader failed";
    }
    writeRecord(sink, 'E', error.size(), [&](AnswerSink& s) { s.write(error.data(), error.size()); });
    ::_exit(0);
}

// ---------------------------------------------------------------- the parent

// The record ended before its bytes did, or the time ran out: the child's status says why.
struct RecordCut {
    bool timedOut = false;
};

// Reads the child's record from the pipe, each wait bounded by the deadline.
class PipeSource final : public AnswerSource {
public:
    PipeSource(int fd, std::chrono::steady_clock::time_point deadline, const std::string& name)
        : fd_(fd), deadline_(deadline), name_(name) {}

    void announce(std::uint64_t size) { left_ = size; }

    void read(void* data, std::size_t size) override {
        if (size > left_)
            throw InputError(format("{}: the reader's answer is damaged ({} bytes wanted, {} left)", name_, size, left_));
        left_ -= size;
        fill(static_cast<char*>(data), size);
    }
    std::uint64_t left() const override { return left_; }

    // Reads exactly `size` bytes, or throws RecordCut: from the buffer, then straight into
    // `data` for a large rest, else through the buffer again.
    void fill(char* data, std::size_t size) {
        for (;;) {
            const std::size_t take = std::min(size, buffered_.size() - at_);
            if (take > 0) std::memcpy(data, buffered_.data() + at_, take);
            at_ += take;
            data += take;
            size -= take;
            if (size == 0) return;
            if (size >= kPipeBuffer) {
                receive(data, size, size);
                return;
            }
            buffered_.resize(kPipeBuffer);
            buffered_.resize(receive(buffered_.data(), buffered_.size(), 1));
            at_ = 0;
        }
    }

    // True if the child wrote nothing more (it closed the pipe) before the deadline.
    bool atEnd() {
        char extra;
        try {
            fill(&extra, 1);
        } catch (const RecordCut& cut) {
            return !cut.timedOut;
        }
        return false;
    }

private:
    // Reads at least `least` and at most `size` bytes into `data`; how many it read.
    std::size_t receive(char* data, std::size_t size, std::size_t least) {
        std::size_t got = 0;
        while (got < least) {
            const auto wait = std::chrono::duration_cast<std::chrono::milliseconds>(deadline_ - std::chrono::steady_clock::now());
            if (wait.count() <= 0) throw RecordCut{true};
            pollfd p{fd_, POLLIN, 0};
            const int ready = ::poll(&p, 1, int(std::min<long long>(wait.count() + 1, 1 << 30)));
            if (ready <= 0) continue;  // interrupted, or the time is up (checked above)
            const ssize_t n = ::read(fd_, data + got, size - got);
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0) throw RecordCut{false};
            got += std::size_t(n);
        }
        return got;
    }

    int fd_;
    std::chrono::steady_clock::time_point deadline_;
    const std::string& name_;
    std::uint64_t left_ = 0;
    std::vector<char> buffered_;  // read from the pipe, not yet taken from [at_, end)
    std::size_t at_ = 0;
};

// True once the child has exited, waiting no later than `deadline` (a pidfd becomes readable
// when its process ends; without one, on an old kernel, this waits as long as it takes).
bool exitsBy(pid_t child, std::chrono::steady_clock::time_point deadline) {
    const int pidfd = int(::syscall(SYS_pidfd_open, child, 0));
    if (pidfd < 0) return true;
    bool exited = false;
    for (;;) {
        const auto wait = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
        pollfd p{pidfd, POLLIN, 0};
        const int ready = ::poll(&p, 1, int(std::clamp<long long>(wait.count() + 1, 0, 1 << 30)));
        if (ready > 0) exited = true;
        if (ready > 0 || (ready == 0 && wait.count() <= 0) || (ready < 0 && errno != EINTR)) break;
    }
    ::close(pidfd);
    return exited;
}

struct ChildEnd {
    int status = 0;
    bool killedAtDeadline = false;  // it closed the pipe but had not exited by the deadline
};

// Reaps the child: killed at once if `kill`, else when it exits, but killed at `deadline` if it
// lingers. Then kills whatever it left behind in its process group.
ChildEnd endChild(pid_t child, bool kill, std::chrono::steady_clock::time_point deadline) {
    ChildEnd end;
    if (!kill && !exitsBy(child, deadline)) end.killedAtDeadline = kill = true;
    if (kill) ::kill(-child, SIGKILL);
    while (::waitpid(child, &end.status, 0) < 0 && errno == EINTR) {
    }
    ::kill(-child, SIGKILL);
    return end;
}

// The ReaderFailure that the child's status, or a cut record, stands for.
ReaderFailure failure(int status, bool timedOut, const std::string& name, std::string_view reader,
                      const ReaderLimits& limits) {
    using Kind = ReaderFailure::Kind;
    const std::string who = format("{}: the {} reader", name, reader);
    if (timedOut) return {Kind::TimedOut, format("{} gave up after {} s (--read-timeout)", who, limits.seconds)};
    if (WIFEXITED(status) && WEXITSTATUS(status) == kOutOfMemoryExit)
        return {Kind::OutOfMemory, format("{} needed more than {} GB (--read-memory)", who, limits.gigabytes)};
    if (WIFSIGNALED(status)) {
        const int signal = WTERMSIG(status);
        if (signal == SIGXCPU)
            return {Kind::TimedOut, format("{} gave up after {} s of processor time (--read-timeout)", who, limits.seconds)};
        const char* abbrev = ::sigabbrev_np(signal);
        return {Kind::Crashed,
                format("{} crashed (signal {}{}{})", who, signal, abbrev ? ", SIG" : "", abbrev ? abbrev : "")};
    }
    return {Kind::NoAnswer,
            format("{} ended without an answer (exit {})", who, WIFEXITED(status) ? WEXITSTATUS(status) : -1)};
}

// The parent's side of one reading: the record's head, then the error or the answer.
void receive(pid_t child, int fd, const std::string& name, std::string_view reader, const ReaderLimits& limits,
             const std::function<void(AnswerSource&)>& consume) {
    const auto deadline = std::chrono::steady_clock::now() +
                          std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                              std::chrono::duration<double>(limits.seconds));
    PipeSource source(fd, deadline, name);
    char kind = 0;
    std::uint64_t size = 0;
    try {
        source.fill(&kind, 1);
        source.fill(reinterpret_cast<char*>(&size), sizeof size);
        if (double(size) > limits.gigabytes * double(1ull << 30))
            throw failure(kOutOfMemoryStatus, false, name, reader, limits);
        source.announce(size);
        if (kind == 'E') {
            std::string message(size, '\0');
            source.read(message.data(), message.size());
            std::replace(message.begin(), message.end(), '\n', ' ');
            throw InputError(message);
        }
        consume(source);
        if (source.left() != 0 || !source.atEnd())
            throw InputError(format("{}: the reader's answer is damaged ({} bytes unread)", name, source.left()));
    } catch (const RecordCut& cut) {
        const ChildEnd end = endChild(child, cut.timedOut, deadline);
        throw failure(end.status, cut.timedOut || end.killedAtDeadline, name, reader, limits);
    } catch (...) {
        endChild(child, true, deadline);  // an error record, a refused answer: the child is not needed any more
        throw;
    }
    if (endChild(child, false, deadline).killedAtDeadline)
        throw failure(0, true, name, reader, limits);  // the answer was whole, but the child would not end
}

}  // namespace

ReaderLimits readerLimits() {
    const std::lock_guard lock(limitsMutex());
    return processLimits();
}

void setReaderLimits(const ReaderLimits& limits) {
    const std::lock_guard lock(limitsMutex());
    processLimits() = limits;
}

void readIsolated(const std::filesystem::path& file, std::string_view reader, const std::function<Answer()>& produce,
                  const std::function<void(AnswerSource&)>& consume) {
    const ReaderLimits limits = readerLimits();
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0)
        throw std::runtime_error(format("cannot make a pipe for the {} reader: {}", reader, std::strerror(errno)));
    ::fcntl(fds[0], F_SETPIPE_SZ, 1 << 20);  // fewer, larger transfers; the default if refused
    const pid_t child = ::fork();
    if (child < 0) {
        ::close(fds[0]);
        ::close(fds[1]);
        throw std::runtime_error(format("cannot start the {} reader: {}", reader, std::strerror(errno)));
    }
    if (child == 0) {
        ::close(fds[0]);
        runChild(fds[1], limits, produce);
    }
    ::close(fds[1]);
    ::setpgid(child, child);  // also set by the child: whichever runs first
    struct Close {
        int fd;
        ~Close() { ::close(fd); }
    } closeRead{fds[0]};
    receive(child, fds[0], file.string(), reader, limits, consume);
}

}  // namespace dawnforge
