// dawnforge: the command line. Argument parsing (CLI11) and error reporting only:
// bad input -> one line on stderr, exit 2; an internal failure -> exit 1.
#include "commands.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/isolate.hpp>

#include <CLI/CLI.hpp>
#include <tbb/global_control.h>

#include <cstdio>
#include <optional>
#include <string>
#include <vector>

namespace {

using namespace dawnforge;

std::vector<cli::Command> addCommands(CLI::App& app, cli::CommonOptions& common) {
    std::vector<cli::Command> commands{cli::addInspect(app, common), cli::addFracture(app, common),
                                       cli::addSimulate(app, common), cli::addVat(app, common),
                                       cli::addAnim(app, common),
                                       cli::addCity(app, common),     cli::addDemo(app, common),
                                       cli::addRender(app, common),   cli::addView(app, common),
                                       cli::addBake(app, common),     cli::addPivots(app, common),
                                       cli::addWorld(app, common)};
    return commands;
}

// "dawnforge fracture: --pieces: ... (see 'dawnforge fracture --help')"
int parseError(const CLI::App& app, const CLI::ParseError& e) {
    std::string where = "dawnforge";
    for (const CLI::App* sub : app.get_subcommands()) where += " " + sub->get_name();
    std::fprintf(stderr, "%s: %s (see '%s --help')\n", where.c_str(), e.what(), where.c_str());
    return static_cast<int>(ExitCode::BadInput);
}

int run(CLI::App& app, std::vector<cli::Command>& commands, const cli::CommonOptions& common, int argc, char** argv) {
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        return parseError(app, e);
    }
    std::optional<tbb::global_control> threadLimit;
    if (common.threads > 0) threadLimit.emplace(tbb::global_control::max_allowed_parallelism, std::size_t(common.threads));
    for (cli::Command& c : commands)
        if (c.app->parsed()) return c.run();
    return static_cast<int>(ExitCode::Internal);
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"dawnforge: city generation, Voronoi fracture, rigid-body destruction baked into VATs, "
                 "and a mobile-style renderer.",
                 "dawnforge"};
    app.require_subcommand(1);
    app.fallthrough();  // options of the tool (-q) after the command name too
    app.set_version_flag("--version", std::string(DAWNFORGE_VERSION));
    cli::CommonOptions common;
    app.add_flag("-q,--quiet", common.quiet, "No progress on stderr");
    ReaderLimits limits = readerLimits();
    app.add_option("--read-timeout", limits.seconds,
                   "Seconds a reader of a user's file (mesh, EXR, PNG) may take before it is stopped")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.add_option("--read-memory", limits.gigabytes, "Gigabytes of memory a reader of a user's file may use")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    app.parse_complete_callback([&limits] { setReaderLimits(limits); });
    std::vector<cli::Command> commands = addCommands(app, common);
    try {
        return run(app, commands, common, argc, argv);
    } catch (const InputError& e) {
        std::fprintf(stderr, "dawnforge: error: %s\n", e.what());
        return static_cast<int>(ExitCode::BadInput);
    } catch (const Cancelled&) {
        std::fprintf(stderr, "dawnforge: cancelled\n");
        return static_cast<int>(ExitCode::Internal);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "dawnforge: internal error: %s\n", e.what());
        return static_cast<int>(ExitCode::Internal);
    }
}
