#pragma once
// format("{}: {} vertices", file, n): each {} is replaced by the next argument as an
// ostream prints it; {{ and }} stand for braces. A stand-in for std::format, which
// Debian 12's g++ 12 does not have yet; swap it out when the compiler has it.
#include <sstream>
#include <string>
#include <string_view>

namespace dawnforge {

namespace detail {
inline void formatTail(std::ostringstream& out, std::string_view f) {
    for (std::size_t i = 0; i < f.size(); ++i) {
        out << f[i];
        if ((f[i] == '{' || f[i] == '}') && i + 1 < f.size() && f[i + 1] == f[i]) ++i;
    }
}
template <typename First, typename... Rest>
void formatTail(std::ostringstream& out, std::string_view f, const First& first, const Rest&... rest) {
    for (std::size_t i = 0; i < f.size(); ++i) {
        if (f[i] == '{' && i + 1 < f.size() && f[i + 1] == '}') {
            out << first;
            formatTail(out, f.substr(i + 2), rest...);
            return;
        }
        out << f[i];
        if ((f[i] == '{' || f[i] == '}') && i + 1 < f.size() && f[i + 1] == f[i]) ++i;
    }
}
}  // namespace detail

template <typename... Args>
std::string format(std::string_view f, const Args&... args) {
    std::ostringstream out;
    detail::formatTail(out, f, args...);
    return std::move(out).str();
}

}  // namespace dawnforge
