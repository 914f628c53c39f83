#include <dawnforge/core/progress.hpp>

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace dawnforge {

bool stderrIsTerminal() { return ::isatty(STDERR_FILENO) == 1; }

StderrProgress::StderrProgress(std::string label, bool enabled) : label_(std::move(label)), enabled_(enabled) {}

StderrProgress::~StderrProgress() {
    if (printed_) std::fprintf(stderr, "\r%s: done\033[K\n", label_.c_str());
}

bool StderrProgress::operator()(double fraction) {
    if (!enabled_) return true;
    const auto now = std::chrono::steady_clock::now();
    if (printed_ && fraction < 1.0 && now - last_ < std::chrono::milliseconds(100)) return true;
    last_ = now;
    printed_ = true;
    std::fprintf(stderr, "\r%s: %3d%%", label_.c_str(), static_cast<int>(std::clamp(fraction, 0.0, 1.0) * 100.0));
    std::fflush(stderr);
    return true;
}

ProgressFn StderrProgress::callback() {
    return [this](double f) { return (*this)(f); };
}

}  // namespace dawnforge
