#pragma once
// The commands of the dawnforge executable: each parses nothing and computes nothing of
// its own; it wires the stages of the libraries together (ARCHITECTURE.md, cli/).
#include <filesystem>
#include <string>

namespace dawnforge::cli {

struct CommonOptions {
    bool quiet = false;  // no progress on stderr
};

struct InspectOptions {
    std::filesystem::path file;
    std::filesystem::path repairOutput;  // empty: no repair
};
int runInspect(const InspectOptions& options, const CommonOptions& common);

struct DemoOptions {
    std::filesystem::path outputDir;
    int floors = 8;
};
int runDemo(const DemoOptions& options, const CommonOptions& common);

}  // namespace dawnforge::cli
