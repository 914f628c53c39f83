#pragma once
// Whole-file input for every reader of the project's files (recipes, scene files, JSON
// reports, raw float arrays): one place that turns a missing or unreadable file into the
// InputError a user can act on.
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace dawnforge {

// The file's bytes; throws InputError "FILE: no such file" or "FILE: cannot be read"
// (a folder, no permission, an I/O error).
std::string readTextFile(const std::filesystem::path& file);
std::vector<std::byte> readBinaryFile(const std::filesystem::path& file);

}  // namespace dawnforge
