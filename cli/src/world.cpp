// dawnforge world plan | build | job: a world built tile by tile (ARCHITECTURE.md, section 9).
#include "commands.hpp"
#include "options.hpp"
#include "world_report.hpp"

#include <dawnforge/core/atomic_file.hpp>
#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/progress.hpp>
#include <dawnforge/core/read_file.hpp>
#include <dawnforge/world/build.hpp>

#include <tbb/global_control.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <regex>

namespace dawnforge::cli {

namespace {

namespace fs = std::filesystem;

struct WorldOptions {
    fs::path dir;
    fs::path recipeFile;
    std::string destroyIds;
    world::WorldSettings plan;
    world::BuildSettings build;
    std::vector<std::string> only;
    std::string stages = "city,bake,hlod,destroy";
    std::string stage;
    int task = -1;
};

std::vector<std::string> splitList(const std::string& text) {
    std::vector<std::string> out;
    std::size_t start = 0;
    while (start <= text.size()) {
        const std::size_t end = std::min(text.find(',', start), text.size());
        if (end > start) out.push_back(text.substr(start, end - start));
        start = end + 1;
    }
    return out;
}

glm::ivec2 parseTileIndex(const std::string& text) {
    static const std::regex kTile(R"(\s*([0-9]{1,6})\s*,\s*([0-9]{1,6})\s*)");
    std::smatch m;
    if (!std::regex_match(text, m, kTile))
        throw InputError(format("--only: expected I,J (a tile's column and row, from 0), e.g. 1,0 (got \"{}\")", text));
    return {std::stoi(m[1].str()), std::stoi(m[2].str())};
}

// The executable running now: the jobs run it again.
fs::path selfExecutable() {
    std::error_code ec;
    const fs::path p = fs::read_symlink("/proc/self/exe", ec);
    if (ec) throw InputError("cannot find the dawnforge executable (/proc/self/exe)");
    return p;
}

int runPlan(WorldOptions& o, const CommonOptions& common) {
    if (!o.recipeFile.empty()) o.plan.recipe = procgen::parseRecipe(readTextFile(o.recipeFile), o.recipeFile.string());
    for (const std::string& id : splitList(o.destroyIds)) {
        char* end = nullptr;
        const long v = std::strtol(id.c_str(), &end, 10);
        if (*end != '\0' || v < 0 || v > 1000000000) throw InputError(format("--destroy-ids: \"{}\" is not a building id", id));
        o.plan.destroy.push_back(int(v));
    }
    const auto start = std::chrono::steady_clock::now();
    world::WorldPlan plan;
    {
        StderrProgress progress = progressFor("world plan", common);
        plan = world::planWorld(o.plan, progress.callback());
    }
    ensureOutputDirectory(o.dir);
    writeFileAtomically(o.dir / "plan.json", world::planJson(plan));
    std::size_t buildings = 0;
    for (const world::WorldTile& t : plan.tiles) buildings += t.buildings.size();
    std::printf("planned %.0f x %.0f m, seed %llu: %d x %d tiles of %.0f m, %zu buildings, %d HLOD levels (%zu nodes), %zu to destroy, in %.2f s\n",
                o.plan.size.x, o.plan.size.y, static_cast<unsigned long long>(o.plan.seed), plan.tileCount.x, plan.tileCount.y,
                o.plan.tileSize, buildings, plan.hlodLevels, plan.hlod.size(), plan.destroy.size(),
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    std::printf("  wrote %s; build it with: dawnforge world build %s\n", (o.dir / "plan.json").string().c_str(), o.dir.string().c_str());
    return 0;
}

int runBuild(WorldOptions& o, const CommonOptions& common) {
    o.build.stages = splitList(o.stages);
    if (o.build.stages.empty()) throw InputError("--stages: name at least one of city, bake, hlod, destroy");
    for (const std::string& t : o.only) o.build.only.push_back(parseTileIndex(t));
    o.build.executable = selfExecutable();
    const bool show = !common.quiet && stderrIsTerminal();
    const world::BuildReport report = world::buildWorld(o.dir, o.build, [&](const std::string& stage, std::size_t done, std::size_t total) {
        if (show) std::fprintf(stderr, "world build: %s %zu of %zu\n", stage.c_str(), done, total);
    });
    std::size_t failures = 0;
    for (const world::StageReport& s : report.stages) {
        std::printf("%-8s %zu jobs: %zu already done, %zu run, %zu failed", s.stage.c_str(), s.jobs, s.skipped, s.ran, s.failed.size());
        if (s.left > 0) std::printf(", %zu left (tiles they need are not built)", s.left);
        std::printf("\n");
        for (const std::string& f : s.failed)
            std::fprintf(stderr, "dawnforge: error: world build: the %s job of %s failed (its log is in %s)\n", s.stage.c_str(), f.c_str(),
                         (o.dir / "logs").string().c_str());
        failures += s.failed.size();
    }
    std::printf("wrote %s\n", writeWorldReport(o.dir, report).string().c_str());  // what was built, failed or not
    if (failures > 0) {
        std::fprintf(stderr, "dawnforge: error: world build: %zu jobs failed; what finished is kept: run the same command again to redo the rest\n",
                     failures);
        return static_cast<int>(ExitCode::Internal);
    }
    std::printf("built %s in %.1f s; wrote %s\n", o.dir.string().c_str(), report.seconds, (o.dir / "tileset.json").string().c_str());
    return 0;
}

int runWorldJob(WorldOptions& o, const CommonOptions& common) {
    // Slurm gives a job its cores in SLURM_CPUS_PER_TASK; --threads overrides it.
    int threads = common.threads;
    if (threads == 0)
        if (const char* cpus = std::getenv("SLURM_CPUS_PER_TASK")) threads = std::max(0, std::atoi(cpus));
    std::optional<tbb::global_control> limit;
    if (threads > 0) limit.emplace(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    world::runJob(o.dir, o.stage, o.task, threads, selfExecutable());
    return 0;
}

void addPlanOptions(CLI::App& cmd, WorldOptions& o) {
    world::WorldSettings& s = o.plan;
    cmd.add_option("DIR", o.dir, "The world's folder (plan.json goes there)")->required();
    cmd.add_option_function<std::string>(
           "--size", [&s](const std::string& text) { s.size = parseSize(text, "--size", "metres"); }, "World size WxD in metres")
        ->default_str(sizeText(s.size));
    cmd.add_option("--tile-size", s.tileSize, "Tile size in metres")->capture_default_str();
    cmd.add_option_function<std::string>(
           "--origin",
           [&s](const std::string& text) {
               const glm::dvec3 o = parsePoint(text, "--origin");
               s.origin = {o.x, o.y, o.z};
           },
           "Where the world's south-west corner lies on the globe (WGS84): LONGITUDE,LATITUDE,HEIGHT in degrees and "
           "metres; tileset.json's root transform puts it there")
        ->default_str(format("{},{},{}", s.origin.longitude, s.origin.latitude, s.origin.height));
    cmd.add_option("--seed", s.seed, "Random seed (the same world as dawnforge city --seed)")->capture_default_str();
    cmd.add_option("--recipe", o.recipeFile, "JSON city recipe (as dawnforge city takes)");
    cmd.add_option("--halo", s.halo, "Metres around a tile that its bake traces against")->capture_default_str();
    cmd.add_option("--destroy", s.destroyPerTile, "Buildings per tile to fracture, simulate and bake into VATs")->capture_default_str();
    cmd.add_option("--destroy-ids", o.destroyIds, "Or these buildings: ids separated by commas");
    cmd.add_option("--bake-texel", s.bake.texel, "Bake: metres per lightmap texel on buildings")->check(CLI::Range(0.01, 10.0))->capture_default_str();
    cmd.add_option("--bake-interior-texel", s.bake.interiorTexel, "Bake: metres per texel in rooms")->check(CLI::Range(0.01, 10.0))->capture_default_str();
    cmd.add_option("--bake-ground-texel", s.bake.groundTexel, "Bake: metres per texel on the ground")->check(CLI::Range(0.05, 50.0))->capture_default_str();
    cmd.add_option("--bake-samples", s.bake.samples, "Bake: rays per texel per pass")->check(CLI::Range(1, 65536))->capture_default_str();
    cmd.add_option("--bake-sun-samples", s.bake.sunSamples, "Bake: sun positions per texel")->check(CLI::Range(1, 4096))->capture_default_str();
    cmd.add_option("--bake-bounces", s.bake.bounces, "Bake: bounces")->check(CLI::Range(0, 16))->capture_default_str();
    cmd.add_option("--bake-halo-texel-scale", s.haloTexelScale, "Bake: the halo's texels (lit, not written) are this many times as large")
        ->check(CLI::Range(1.0, 64.0))->capture_default_str();
    cmd.add_option("--bake-memory-budget", s.bake.memoryBudgetMb, "Bake: the most memory one tile's bake may need (MB)")
        ->check(CLI::Range(64.0, 1.0e7))->capture_default_str();
}

void addBuildOptions(CLI::App& cmd, WorldOptions& o) {
    world::BuildSettings& b = o.build;
    cmd.add_option("DIR", o.dir, "A world folder written by dawnforge world plan")->required();
    cmd.add_option("--backend", b.backend, "Where the jobs run: local (this machine) or slurm (sbatch job arrays)")->capture_default_str();
    cmd.add_option("--jobs", b.jobs, "local: jobs at once (0: one per core, no more than the memory holds bakes)")->capture_default_str();
    cmd.add_option("--threads-per-job", b.threadsPerJob, "Cores per job (0: the cores / --jobs; slurm: 1)")->check(CLI::Range(0, 1024))->capture_default_str();
    cmd.add_option("--stages", o.stages, "Stages to run, separated by commas")->capture_default_str();
    cmd.add_option("--only", o.only, "Only this tile I,J (repeat for more); HLOD nodes and destroyed buildings over them");
    cmd.add_option("--partition", b.partition, "slurm: the partition (default: the cluster's)");
    cmd.add_option("--mem", b.memoryMb, "slurm: memory per job in MB (0: the plan's bake budget + 512)")
        ->check(CLI::Range(0, 10000000))->capture_default_str();
}

}  // namespace

Command addWorld(CLI::App& app, CommonOptions& common) {
    auto o = std::make_shared<WorldOptions>();
    CLI::App* cmd = app.add_subcommand("world", "A world in tiles: plan it, then build it with jobs on this machine or on Slurm");
    cmd->require_subcommand(1);
    CLI::App* plan = cmd->add_subcommand("plan", "Plan a world: DIR/plan.json (tiles, owners, halos, HLOD quadtree, jobs)");
    addPlanOptions(*plan, *o);
    CLI::App* build = cmd->add_subcommand("build", "Build a planned world: tiles, bakes, HLOD, destruction, DIR/tileset.json");
    addBuildOptions(*build, *o);
    CLI::App* job = cmd->add_subcommand("job", "Run one job of a world (what world build's backends run)");
    job->add_option("DIR", o->dir, "The world folder")->required();
    job->add_option("--stage", o->stage, "city, bake, hlod1, hlod2, ..., destroy")->required();
    job->add_option("--task", o->task, "The job's index in its stage (plan.json's jobs)")->required()->check(CLI::NonNegativeNumber);
    addThreadsOption(*job, common);
    return {cmd, [o, &common, plan, build] {
                if (plan->parsed()) return runPlan(*o, common);
                if (build->parsed()) return runBuild(*o, common);
                return runWorldJob(*o, common);
            }};
}

}  // namespace dawnforge::cli
