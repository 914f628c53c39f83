// The jobs of `world build` (jobs.hpp): a tile's city, its bake with its halo, an HLOD node,
// a destroyed building.
#include "jobs.hpp"

#include "hlod.hpp"

#include <dawnforge/bake/bake.hpp>
#include <dawnforge/core/atomic_file.hpp>
#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/import.hpp>
#include <dawnforge/core/read_file.hpp>
#include <dawnforge/exporters/gltf.hpp>
#include <dawnforge/exporters/material_images.hpp>
#include <dawnforge/exporters/pivot_painter.hpp>
#include <dawnforge/procgen/city.hpp>

#include <nlohmann/json.hpp>

#include <glm/gtc/matrix_transform.hpp>

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>

extern char** environ;

namespace dawnforge::world {

namespace fs = std::filesystem;

namespace {

// A temporary folder beside `target`, removed with what is left in it unless released.
struct Scratch {
    fs::path dir;
    explicit Scratch(const fs::path& target) : dir(target.parent_path() / format(".{}.partial-{}", target.filename().string(), ::getpid())) {
        std::error_code ec;
        fs::remove_all(dir, ec);
        ensureOutputDirectory(dir);
    }
    ~Scratch() {
        std::error_code ec;
        fs::remove_all(dir, ec);
    }
};

// Moves `from` to `to`, replacing whatever `to` was (a file or a folder).
void replace(const fs::path& from, const fs::path& to) {
    std::error_code ec;
    if (fs::is_directory(to, ec)) fs::remove_all(to);
    fs::rename(from, to);
}

glm::ivec2 tileOfTask(const WorldPlan& plan, int task) {
    return plan.tiles[std::size_t(task)].index;
}

std::string tileDir(glm::ivec2 tile) { return "tiles/" + tileName(tile); }

// How a GLB `up` folders below the world links the world's material pictures, textures/*.png,
// which this writes first where they are missing (each job may be the first; they are the same bytes).
exporters::GltfSettings linkedPictures(const fs::path& worldDir, const std::string& up) {
    exporters::writeMaterialImages(worldDir / "textures");
    return {.images = exporters::MaterialImages::kLinked, .imageFolder = up + "textures/"};
}

// tiles/I_J/city.glb, city.json and trees/: the tile in its own frame (`city --tile` moved to
// the tile's south-west corner).
std::vector<std::string> cityJob(const fs::path& worldDir, const WorldPlan& plan, glm::ivec2 tile) {
    procgen::City city = procgen::generateCity(tileCitySettings(plan, tile));
    const std::string report = procgen::cityReportJson(city);
    const std::vector<procgen::TreeSpecies> species = city.dressing.species;
    const Scene scene = procgen::takeCityScene(city);
    const fs::path dir = worldDir / tileDir(tile);
    Scratch scratch(dir / "city");
    exporters::writeGlb(scene, scratch.dir / "city.glb", linkedPictures(worldDir, "../../"));
    writeFileAtomically(scratch.dir / "city.json", report);
    for (const procgen::TreeSpecies& s : species)
        exporters::writePivotPainter(exporters::buildPivotPainter(procgen::speciesNodes(s), exporters::PivotPreset::Unreal, s.name),
                                     scratch.dir / "trees", s.name);
    std::vector<std::string> outputs;
    for (const char* name : {"trees", "city.json", "city.glb"}) {
        replace(scratch.dir / name, dir / name);
        outputs.push_back(tileDir(tile) + "/" + name);
    }
    return outputs;
}

glm::mat4 localMatrix(const Node& n) {
    return glm::translate(glm::mat4(1.0f), n.translation) * glm::mat4_cast(n.rotation) * glm::scale(glm::mat4(1.0f), n.scale);
}

// The scene's nodes that show a mesh, with world matrices, depth first; `root` gets the name of
// each one's root node.
std::vector<MeshNode> sceneNodes(const Scene& scene, std::vector<std::string>& root) {
    std::vector<MeshNode> out;
    struct Item { std::uint32_t node; glm::mat4 parent; std::uint32_t root; };
    std::vector<Item> stack;
    for (auto it = scene.roots.rbegin(); it != scene.roots.rend(); ++it) stack.push_back({*it, glm::mat4(1.0f), *it});
    while (!stack.empty()) {
        const Item item = stack.back();
        stack.pop_back();
        const Node& n = scene.nodes[item.node];
        const glm::mat4 world = item.parent * localMatrix(n);
        if (n.mesh >= 0) {
            out.push_back({n.name, world, scene.meshes[std::size_t(n.mesh)], -1});
            root.push_back(scene.nodes[item.root].name);
        }
        for (auto c = n.children.rbegin(); c != n.children.rend(); ++c) stack.push_back({*c, world, item.root});
    }
    return out;
}

// tiles/I_J/bake/: the tile's buildings and ground, lit with its halo (the neighbours' buildings
// within plan.settings.halo and their ground tiles), which this job generates itself.
std::vector<std::string> bakeJob(const fs::path& worldDir, const WorldPlan& plan, glm::ivec2 tile) {
    const fs::path dir = worldDir / tileDir(tile);
    bake::BakeRegion region;
    {
        // The tile's city.glb, byte for byte as the city job writes it: bake.json binds to it.
        procgen::City own = procgen::generateCity(tileCitySettings(plan, tile));
        region.cityJson = procgen::cityReportJson(own);
        Scratch scratch(dir / "bake-city");
        exporters::writeGlb(procgen::takeCityScene(own), scratch.dir / "city.glb", linkedPictures(worldDir, "../../"));
        region.cityGlb = readBinaryFile(scratch.dir / "city.glb");
    }
    procgen::City city = procgen::generateCity(tileCitySettings(plan, tile, plan.settings.halo));
    region.regionCityJson = procgen::cityReportJson(city);
    std::vector<std::string> roots;
    const Scene scene = procgen::takeCityScene(city);
    region.nodes = sceneNodes(scene, roots);
    const std::string own = "tile_" + tileName(tile);
    for (const std::string& r : roots) region.halo.push_back(r != own);
    region.haloTexelScale = plan.settings.haloTexelScale;
    const bake::BakeReport report = bake::bakeRegion(region, dir, plan.settings.bake);
    std::printf("baked tile %s: %zu buildings, %zu receivers, %zu texels, about %.0f MB, %.1f s (lighting %.1f s)\n",
                tileName(tile).c_str(), report.buildings, report.receivers, report.texels, report.estimatedMb, report.seconds,
                report.lightingSeconds);
    return {tileDir(tile) + "/bake"};
}

// A node's frame: the plan point at the south-west corner of its first tile.
glm::dvec2 nodeOrigin(const WorldPlan& plan, const HlodNode& node) {
    return glm::dvec2(node.index * (1 << node.level)) * plan.settings.tileSize;
}

// Moves a mesh from the frame at plan point `from` to the frame at `to`.
void moveFrame(Mesh& mesh, glm::dvec2 from, glm::dvec2 to) {
    const glm::dvec2 d = from - to;
    for (glm::vec3& p : mesh.positions) p = glm::vec3(float(double(p.x) + d.x), p.y, float(double(p.z) - d.y));
}

std::string hlodFile(const HlodNode& node) { return "hlod/" + hlodName(node); }

// hlod/L_X_Y.glb and .json: a level-1 node merges its tiles (tileHlodSource), a higher one its
// four children's meshes; the error adds the largest child's.
std::vector<std::string> hlodJob(const fs::path& worldDir, const WorldPlan& plan, const HlodNode& node) {
    const glm::dvec2 origin = nodeOrigin(plan, node);
    std::vector<Mesh> children;
    std::vector<std::string> childNames;
    double childError = 0.0;
    std::size_t sourceTriangles = 0;
    if (node.level == 1) {
        for (glm::ivec2 t : node.tiles) {
            children.push_back(tileHlodSource(worldDir / tileDir(t)));
            moveFrame(children.back(), glm::dvec2(t) * plan.settings.tileSize, origin);
            childNames.push_back(tileName(t));
        }
    } else {
        for (const HlodNode& c : plan.hlod) {
            if (c.level != node.level - 1 || c.index / 2 != node.index) continue;
            const fs::path file = worldDir / (hlodFile(c) + ".glb");
            for (MeshNode& n : loadMeshNodes(file, ReadIn::thisProcess)) children.push_back(std::move(n.mesh));
            moveFrame(children.back(), nodeOrigin(plan, c), origin);
            const nlohmann::json j = nlohmann::json::parse(readTextFile(worldDir / (hlodFile(c) + ".json")));
            childError = std::max(childError, j.at("geometric_error").get<double>());
            childNames.push_back(hlodName(c));
        }
    }
    for (const Mesh& m : children) sourceTriangles += m.triangleCount();
    HlodMesh result = simplifyHlod(children);
    const std::string name = hlodName(node);
    result.mesh.name = "hlod_" + name;
    Scene scene;
    scene.addMeshNode(std::move(result.mesh));
    const std::size_t triangles = scene.meshes.front().triangleCount();
    ensureOutputDirectory(worldDir / "hlod");
    exporters::writeGlb(scene, worldDir / (hlodFile(node) + ".glb"), linkedPictures(worldDir, "../"));
    nlohmann::ordered_json j{{"name", name},
                             {"level", node.level},
                             {"origin", {origin.x, origin.y}},
                             {"children", childNames},
                             {"source_triangles", sourceTriangles},
                             {"triangles", triangles},
                             {"simplifier_error", result.error},
                             {"geometric_error", result.error + childError}};
    writeFileAtomically(worldDir / (hlodFile(node) + ".json"), j.dump(1) + "\n");
    return {hlodFile(node) + ".glb", hlodFile(node) + ".json"};
}

// Runs `argv` with this process's stdout and stderr (the job's log); throws when it fails.
void runCommand(const std::vector<std::string>& argv) {
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    std::fflush(nullptr);
    pid_t pid = 0;
    if (const int err = ::posix_spawn(&pid, args[0], nullptr, nullptr, args.data(), environ); err != 0)
        throw InputError(format("could not start {}: {}", argv[0], std::strerror(err)));
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {}
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
        throw InputError(format("dawnforge {} failed ({})", argv[1],
                                WIFEXITED(status) ? format("exit code {}", WEXITSTATUS(status)) : format("signal {}", WTERMSIG(status))));
}

// destroy/building_NNNNN/: the building fractured by material in its tile's city, collapsed
// (every bond breaks at the trigger) and baked into VATs for the runtime and both engines.
std::vector<std::string> destroyJob(const fs::path& worldDir, const DestroyJob& job, int threads, const fs::path& exe) {
    const std::string name = buildingName(job.building);
    const fs::path target = worldDir / "destroy" / name;
    ensureOutputDirectory(worldDir / "destroy");
    Scratch scratch(target);
    const std::string e = exe.string(), d = scratch.dir.string(), t = std::to_string(threads);
    runCommand({e, "fracture", (worldDir / tileDir(job.tile)).string(), "--building", std::to_string(job.building), "-o",
                d + "/fracture", "--threads", t});
    runCommand({e, "simulate", d + "/fracture", "-o", d + "/sim", "--collapse", "--threads", t});
    for (const char* preset : {"native", "unreal", "unity"})
        runCommand({e, "vat", d + "/sim", "-o", d + "/vat/" + preset, "--preset", preset, "--name", name});
    replace(scratch.dir, target);
    return {"destroy/" + name};
}

}  // namespace

std::vector<std::string> stageJobs(const WorldPlan& plan, const std::string& stage) {
    std::vector<std::string> jobs;
    if (stage == "city" || stage == "bake")
        for (const WorldTile& t : plan.tiles) jobs.push_back(tileName(t.index));
    else if (stage == "destroy")
        for (const DestroyJob& d : plan.destroy) jobs.push_back(buildingName(d.building));
    else
        for (const HlodNode* n : hlodStageNodes(plan, stage)) jobs.push_back(hlodName(*n));
    return jobs;
}

std::vector<std::string> expandStages(const WorldPlan& plan, const std::vector<std::string>& stages) {
    std::vector<std::string> out;
    for (const char* known : kStages) {
        if (std::find(stages.begin(), stages.end(), known) == stages.end()) continue;
        if (std::string(known) != "hlod") out.push_back(known);
        else
            for (int level = 1; level <= plan.hlodLevels; ++level) out.push_back(hlodStage(level));
    }
    return out;
}

std::vector<std::string> runStageJob(const fs::path& worldDir, const WorldPlan& plan, const std::string& stage, int task,
                                     int threads, const fs::path& executable) {
    const std::vector<std::string> jobs = stageJobs(plan, stage);
    if (task < 0 || std::size_t(task) >= jobs.size())
        throw InputError(format("--task {}: stage \"{}\" has {} jobs in this plan", task, stage, jobs.size()));
    if (stage == "city") return cityJob(worldDir, plan, tileOfTask(plan, task));
    if (stage == "bake") return bakeJob(worldDir, plan, tileOfTask(plan, task));
    if (stage == "destroy") return destroyJob(worldDir, plan.destroy[std::size_t(task)], threads, executable);
    return hlodJob(worldDir, plan, *hlodStageNodes(plan, stage)[std::size_t(task)]);
}

}  // namespace dawnforge::world
