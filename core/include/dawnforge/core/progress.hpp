#pragma once
// Long work reports progress and can be asked to stop (STYLE.md 13).
#include <chrono>
#include <functional>
#include <string>

namespace dawnforge {

// Called with the fraction done in [0, 1]; returns false to ask the work to stop
// (the work then throws Cancelled). The default is a no-op that never stops.
using ProgressFn = std::function<bool(double fraction)>;
inline bool noProgress(double) { return true; }

bool stderrIsTerminal();

// Prints "label: 42%" on stderr, redrawn in place, at most ten times a second; silent
// unless enabled (the CLI enables it when stderr is a terminal and --quiet is not given).
class StderrProgress {
public:
    StderrProgress(std::string label, bool enabled);
    ~StderrProgress();
    bool operator()(double fraction);
    ProgressFn callback();

private:
    std::string label_;
    bool enabled_;
    bool printed_ = false;
    std::chrono::steady_clock::time_point last_{};
};

}  // namespace dawnforge
