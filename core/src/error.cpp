#include <dawnforge/core/error.hpp>

#include <cstdio>
#include <cstdlib>

namespace dawnforge {

void assertionFailed(const char* function, const char* message) {
    std::fprintf(stderr, "dawnforge::%s(): %s\n", function, message);
    std::abort();
}

}  // namespace dawnforge
