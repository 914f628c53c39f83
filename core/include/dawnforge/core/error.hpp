#pragma once
// Two kinds of failure (docs/STYLE.md 5): bad input from a user is an InputError carrying a
// sentence they can act on (the CLI prints it as one line and exits 2); a programmer's
// mistake is DAWNFORGE_ASSERT, which names the function and aborts.
#include <stdexcept>
#include <string>

namespace dawnforge {

enum class ExitCode : int {
    Ok = 0,
    Internal = 1,  // a bug or an environment failure: not the user's input
    BadInput = 2,  // a missing/unparsable file, an invalid mesh, an out-of-range option
};

// Bad input: the message names the input and the problem, on one line.
class InputError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// Bad input that a repair (repairMesh in validate.hpp) may fix: an open, non-manifold or
// self-intersecting mesh where a closed solid is needed.
class RepairableMeshError : public InputError {
public:
    using InputError::InputError;
};

// Work stopped on request (a progress callback returned false).
class Cancelled : public std::runtime_error {
public:
    Cancelled() : std::runtime_error("cancelled") {}
};

[[noreturn]] void assertionFailed(const char* function, const char* message);

// A library's error message (a JSON, OBJ, glTF or EXR parser's) fit for an InputError: on one line,
// without a leading "[tag] " such as nlohmann's "[json.exception.parse_error.101] ".
std::string oneLine(std::string message);

}  // namespace dawnforge

#define DAWNFORGE_ASSERT(condition, message)                                  \
    do {                                                                      \
        if (!(condition)) ::dawnforge::assertionFailed(__func__, (message));  \
    } while (false)
