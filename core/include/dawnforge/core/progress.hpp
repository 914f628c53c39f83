#pragma once
// Long work reports progress and can be asked to stop (docs/STYLE.md 13).
#include <chrono>
#include <functional>
#include <string>
#include <type_traits>

namespace dawnforge {

inline bool noProgress(double) { return true; }

// Called with the fraction done in [0, 1]; returns false to ask the work to stop (the work
// then throws Cancelled). Never empty, like OpenVDB's interrupter: a default-constructed
// one, or one made from an empty function, is the no-op noProgress, so long work calls it
// without checking.
class ProgressFn {
public:
    ProgressFn() = default;
    template <typename F>
        requires std::is_invocable_r_v<bool, F&, double> && (!std::is_same_v<std::decay_t<F>, ProgressFn>)
    ProgressFn(F f) : fn_(std::move(f)) {  // NOLINT(google-explicit-constructor): any callable is a progress
        if (!fn_) fn_ = noProgress;
    }
    bool operator()(double fraction) const { return fn_(fraction); }

private:
    std::function<bool(double)> fn_ = noProgress;
};

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
