#pragma once
// DIR/report.html: one self-contained page of what `demo` or `world build` made (ARCHITECTURE.md,
// section 4.8): the pictures, each stage's outputs and time, the bake's four channels of one
// building, the simulation's energy and pieces in motion, the fracture's piece sizes. Images
// are inlined as data: URIs and plots as SVG; the page needs no script and no other file.
#include <filesystem>
#include <string>
#include <vector>

namespace dawnforge::cli {

struct ReportPicture {
    std::string caption;
    std::filesystem::path file;  // a PNG
};

struct ReportStage {
    std::string name;
    std::string made;                            // one line: what it made
    std::vector<std::filesystem::path> outputs;  // files or folders, relative to the report's folder
    double seconds = -1.0;                       // wall time; < 0: not measured
};

struct ReportInputs {
    std::string title;
    std::vector<ReportPicture> pictures;
    std::vector<ReportStage> stages;
    std::filesystem::path bakeDir;      // a bake folder (section 4.11); empty: none
    int bakeBuilding = -1;              // the building whose lightmap to show; -1: the bake's first
    std::filesystem::path fractureDir;  // fracture.json: the pieces' volumes, masses, inertias
    std::filesystem::path simDir;       // sim.json and transforms.bin of that fracture
};

// The page. A part whose input is missing or unreadable says "not available" and why; it
// never throws for one.
std::string reportHtml(const ReportInputs& inputs, const std::filesystem::path& dir);

// Writes DIR/report.html atomically and returns its path. Throws only when it cannot write.
std::filesystem::path writeReport(const ReportInputs& inputs, const std::filesystem::path& dir);

}  // namespace dawnforge::cli
