// dawnforge bake CITY_DIR: lightmaps, overlook maps and proxies into CITY_DIR/bake/.
#include "commands.hpp"
#include "folders.hpp"

#include <dawnforge/bake/bake.hpp>
#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>

#include <cstdio>
#include <memory>

namespace dawnforge::cli {

namespace {

struct BakeOptions {
    std::filesystem::path cityDir;
    bake::BakeSettings settings;
};

}  // namespace

void bakeCityFolder(const std::filesystem::path& cityDir, const bake::BakeSettings& settings, const CommonOptions& common) {
    bake::BakeReport report;
    try {
        StderrProgress progress = progressFor("bake", common);
        report = bake::bakeCity(cityDir, settings, progress.callback());
    } catch (const bake::BakeBudgetError& e) {
        throw InputError(format("{} (raise --texel, --interior-texel and --ground-texel, or --memory-budget)", e.what()));
    }
    const double mrays = double(report.lighting.rays) / std::max(report.lighting.raySeconds, 1e-9) / 1e6;
    std::printf("baked %s: %zu buildings, %zu rooms, %zu lamps, %zu lightmaps with %zu texels, %zu proxies in %.1f s\n",
                cityDir.string().c_str(), report.buildings, report.rooms, report.lamps, report.receivers, report.texels,
                report.proxies, report.seconds);
    std::printf("  %zu rays in %.1f s (%.2f Mrays/s) on %zu triangles; load %.1f s, charts %.1f s, lighting %.1f s, files %.1f s\n",
                report.lighting.rays, report.lighting.raySeconds, mrays, report.triangles, report.loadSeconds, report.layoutSeconds,
                report.lightingSeconds, report.writeSeconds);
    std::printf("  wrote %s\n", (cityDir / "bake").string().c_str());
}

Command addBake(CLI::App& app, CommonOptions& common) {
    auto o = std::make_shared<BakeOptions>();
    bake::BakeSettings& s = o->settings;
    CLI::App* cmd = app.add_subcommand(
        "bake", "Bake lightmaps (sky, sun bounce, AO, lamps), overlook maps and proxies next to a city: CITY_DIR/bake/");
    cmd->footer(
        "Writes CITY_DIR/bake/: bake.json, one RGBA lightmap (.png: R sky, G sun bounce, B AO, A lamps) and its UV set "
        "(.uv) per building and ground tile, overlook.exr (depth, ground and roof heights) and proxies.json. render, "
        "view and demo use it when it is there. A failed bake leaves the old folder (or none) and nothing half-written.");
    cmd->add_option("CITY_DIR", o->cityDir, "A folder written by dawnforge city (city.glb, city.json)")->required();
    cmd->add_option("--texel", s.texel, "Metres per lightmap texel on buildings (LOD1 shells: twice that)")
        ->check(CLI::Range(0.01, 10.0))->capture_default_str();
    cmd->add_option("--interior-texel", s.interiorTexel, "Metres per lightmap texel in rooms")
        ->check(CLI::Range(0.01, 10.0))->capture_default_str();
    cmd->add_option("--ground-texel", s.groundTexel, "Metres per lightmap texel on the ground")
        ->check(CLI::Range(0.05, 50.0))->capture_default_str();
    cmd->add_option("--samples", s.samples, "Hemisphere rays per texel per pass")->check(CLI::Range(1, 65536))->capture_default_str();
    cmd->add_option("--sun-samples", s.sunSamples, "Sun positions per texel along the day's path")
        ->check(CLI::Range(1, 4096))->capture_default_str();
    cmd->add_option("--bounces", s.bounces, "Bounces of sky, sun and lamp light")->check(CLI::Range(0, 16))->capture_default_str();
    cmd->add_option("--ao-radius", s.aoRadius, "Ambient-occlusion radius in metres")->check(CLI::Range(0.001, 100.0))->capture_default_str();
    cmd->add_option("--memory-budget", s.memoryBudgetMb, "Refuse settings that need more memory than this (MB)")
        ->check(CLI::Range(64.0, 1e9))->capture_default_str();
    cmd->add_option("--seed", s.seed, "Random seed of the ray directions")->capture_default_str();
    addThreadsOption(*cmd, common);
    return {cmd, [o, &common] {
                bakeCityFolder(o->cityDir, o->settings, common);
                return 0;
            }};
}

}  // namespace dawnforge::cli
