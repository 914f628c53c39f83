#include "commands.hpp"

#include <dawnforge/core/import.hpp>
#include <dawnforge/core/validate.hpp>
#include <dawnforge/exporters/gltf.hpp>

#include <nlohmann/json.hpp>

#include <iostream>
#include <memory>

namespace dawnforge::cli {

namespace {

nlohmann::ordered_json reportJson(const MeshReport& r) {
    nlohmann::ordered_json j;
    j["triangles"] = r.triangles;
    j["vertices"] = r.vertices;
    j["attribute_vertices"] = r.attributeVertices;
    j["closed"] = r.closed;
    j["manifold"] = r.manifold;
    j["self_intersecting"] = r.selfIntersecting;
    j["consistently_oriented"] = r.consistentlyOriented;
    j["outward_oriented"] = r.outwardOriented;
    j["volume"] = r.volume ? nlohmann::ordered_json(*r.volume) : nlohmann::ordered_json(nullptr);
    j["area"] = r.area;
    j["bbox_min"] = {r.bounds.min.x, r.bounds.min.y, r.bounds.min.z};
    j["bbox_max"] = {r.bounds.max.x, r.bounds.max.y, r.bounds.max.z};
    j["components"] = r.components;
    j["boundary_edges"] = r.boundaryEdges;
    j["non_manifold_edges"] = r.nonManifoldEdges;
    j["non_manifold_vertices"] = r.nonManifoldVertices;
    j["degenerate_triangles"] = r.degenerateTriangles;
    return j;
}

struct InspectOptions {
    std::filesystem::path file;
    std::filesystem::path repairOutput;  // empty: no repair
};

int runInspect(const InspectOptions& options) {
    const Mesh mesh = loadMesh(options.file);
    nlohmann::ordered_json out;
    out["file"] = options.file.string();
    out.update(reportJson(inspectMesh(mesh)));
    if (!options.repairOutput.empty()) {
        RepairReport repair;
        Mesh fixed = repairFile(mesh, options.file, &repair);
        Scene scene;
        scene.addMeshNode(fixed);
        exporters::writeGlb(scene, options.repairOutput);
        nlohmann::ordered_json r;
        r["output"] = options.repairOutput.string();
        r["actions"] = repair.actions;
        r["result"] = reportJson(inspectMesh(fixed));
        out["repair"] = std::move(r);
    }
    std::cout << out.dump(2) << '\n';
    return 0;
}

}  // namespace

Command addInspect(CLI::App& app, CommonOptions&) {
    auto options = std::make_shared<InspectOptions>();
    CLI::App* cmd = app.add_subcommand(
        "inspect", "Report on a mesh as JSON on stdout: triangles, vertices, closed, manifold, "
                   "self_intersecting, volume, bbox_min, bbox_max, ...");
    cmd->add_option("FILE", options->file, "Mesh file: glTF/GLB, OBJ, FBX, STL, PLY, OFF, DAE, 3DS, ...")->required();
    cmd->add_option("--repair", options->repairOutput,
                    "Also write a repaired copy (GLB): duplicate points merged, degenerate triangles "
                    "removed, orientation made consistent, borders stitched, holes filled");
    return {cmd, [options] { return runInspect(*options); }};
}

}  // namespace dawnforge::cli
