// Example 4: generate a city in code, the way `dawnforge city` does, and write its two files.
//
//   build/bin/example_04_generate_city OUT_DIR [SEED]
//
// writes OUT_DIR/city.glb (the meshes) and OUT_DIR/city.json (the plan and the counts) and
// prints what it made. `example_05_render_headless OUT_DIR picture.png` draws it.
//
// A city comes from a recipe (every parameter, with the defaults `dawnforge city` uses) and a
// few settings (seed, size, tiles). The same recipe, seed and size give byte-identical files
// on any machine and thread count.
#include <dawnforge/core/atomic_file.hpp>
#include <dawnforge/core/error.hpp>
#include <dawnforge/exporters/gltf.hpp>
#include <dawnforge/procgen/city.hpp>
#include <dawnforge/procgen/recipe.hpp>

#include <cstdio>
#include <cstdlib>
#include <filesystem>

int main(int argc, char** argv) {
    if (argc != 2 && argc != 3) {
        std::fprintf(stderr, "usage: %s OUT_DIR [SEED]\n", argv[0]);
        return 2;
    }
    using namespace dawnforge;
    const std::filesystem::path outDir = argv[1];

    // The recipe: start from the defaults and change what this town should look like. A
    // recipe can also come from JSON (procgen::parseRecipe, as examples/recipes/*.json);
    // keys are the snake_case names of these fields.
    procgen::CitySettings settings;
    settings.recipe.coast.water = 0.3;             // the southern 30 % is sea
    settings.recipe.buildings.minFloors = 2;
    settings.recipe.buildings.maxFloors = 5;
    settings.recipe.roofs.flat = 0.1;              // roof types are drawn by weight: mostly pitched
    settings.recipe.roofs.gable = 0.5;
    settings.seed = argc == 3 ? std::strtoull(argv[2], nullptr, 10) : 1;
    settings.size = {200.0, 160.0};                // metres, x (east) by y (north)
    settings.tileSize = 100.0;                     // city.glb gets one root node per 100 m tile

    try {
        // Plan (streets, coast, blocks, lots), then every building in parallel, each from its
        // own sub-seed. Throws InputError for a recipe or size out of range.
        procgen::City city = procgen::generateCity(settings);

        // What was made: the same counts city.json records.
        const procgen::CityCounts counts = procgen::countCity(city);
        std::printf("%zu streets, %zu blocks, %zu buildings, %zu floors, %zu rooms, %zu windows\n",
                    city.plan.streets.size(), city.plan.blocks.size(), counts.buildings, counts.floors, counts.rooms,
                    counts.windows);
        std::printf("triangles: LOD0 %zu, LOD1 %zu, ground %zu\n", counts.trianglesLod0, counts.trianglesLod1,
                    counts.trianglesGround);

        // city.json first: takeCityScene moves the meshes out of `city`.
        const std::string report = procgen::cityReportJson(city);
        const Scene scene = procgen::takeCityScene(city);

        // Both files are written to a temporary name and renamed: never half-written.
        ensureOutputDirectory(outDir);
        exporters::writeGlb(scene, outDir / "city.glb");
        writeFileAtomically(outDir / "city.json", report);
        std::printf("wrote %s and %s\n", (outDir / "city.glb").string().c_str(), (outDir / "city.json").string().c_str());
    } catch (const InputError& e) {
        std::fprintf(stderr, "%s\n", e.what());
        return 2;
    }
    return 0;
}
