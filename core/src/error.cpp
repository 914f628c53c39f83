#include <dawnforge/core/error.hpp>

#include <cstdio>
#include <cstdlib>

namespace dawnforge {

void assertionFailed(const char* function, const char* message) {
    std::fprintf(stderr, "dawnforge::%s(): %s\n", function, message);
    std::abort();
}

std::string oneLine(std::string message) {
    if (!message.empty() && message.front() == '[') {
        const std::size_t end = message.find("] ");
        if (end != std::string::npos) message.erase(0, end + 2);
    }
    for (char& c : message)
        if (c == '\n' || c == '\r' || c == '\t') c = ' ';
    while (!message.empty() && message.back() == ' ') message.pop_back();
    return message;
}

}  // namespace dawnforge
