#pragma once
// The commands of the dawnforge executable. Each adds itself to the command line with its
// options bound straight to its library's settings struct (so `--help` shows the library's
// defaults), and returns how to run it; running wires the stages of the libraries together
// and computes nothing of its own (ARCHITECTURE.md, cli/).
#include "options.hpp"

#include <CLI/CLI.hpp>

#include <functional>

namespace dawnforge::cli {

struct Command {
    CLI::App* app;             // parsed() tells whether it was given
    std::function<int()> run;  // its exit code; throws InputError for bad input
};

Command addInspect(CLI::App& app, CommonOptions& common);
Command addFracture(CLI::App& app, CommonOptions& common);
Command addSimulate(CLI::App& app, CommonOptions& common);
Command addVat(CLI::App& app, CommonOptions& common);
Command addAnim(CLI::App& app, CommonOptions& common);
Command addCity(CLI::App& app, CommonOptions& common);
Command addDemo(CLI::App& app, CommonOptions& common);
Command addRender(CLI::App& app, CommonOptions& common);
Command addView(CLI::App& app, CommonOptions& common);
Command addBake(CLI::App& app, CommonOptions& common);
Command addPivots(CLI::App& app, CommonOptions& common);
Command addWorld(CLI::App& app, CommonOptions& common);

}  // namespace dawnforge::cli
