#include "trees.hpp"

#include "city_gpu.hpp"
#include "static_vertex.hpp"

#include <dawnforge/core/leaves.hpp>

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <limits>

namespace dawnforge::runtime {

namespace {

bool isTreeNode(const MeshNode& n) { return n.name.starts_with("tree_"); }

// One tree: its nodes, the trunk first, in the file's order.
struct TreeNodes {
    std::vector<std::size_t> nodes;
};

// Whether two trees show the same meshes element by element (the same species).
bool sameSpecies(const std::vector<MeshNode>& all, const TreeNodes& a, const TreeNodes& b) {
    if (a.nodes.size() != b.nodes.size()) return false;
    for (std::size_t k = 0; k < a.nodes.size(); ++k) {
        const Mesh &ma = all[a.nodes[k]].mesh, &mb = all[b.nodes[k]].mesh;
        if (ma.positions != mb.positions || ma.indices != mb.indices) return false;
    }
    return true;
}

// The tree's elements in its trunk's space, parents as indices among them.
std::vector<MeshNode> treeSpaceNodes(const std::vector<MeshNode>& all, const TreeNodes& tree) {
    const glm::mat4 toTree = glm::inverse(all[tree.nodes[0]].world);
    std::vector<MeshNode> out;
    for (std::size_t k = 0; k < tree.nodes.size(); ++k) {
        const MeshNode& n = all[tree.nodes[k]];
        MeshNode local{n.name, toTree * n.world, n.mesh, -1};
        if (k > 0 && n.parent >= 0) {
            const auto parent = std::find(tree.nodes.begin(), tree.nodes.end(), std::size_t(n.parent));
            if (parent != tree.nodes.end()) local.parent = int(parent - tree.nodes.begin());
        }
        out.push_back(std::move(local));
    }
    return out;
}

// Which tree each node belongs to (-1: none): a "tree_" node with its "tree_" descendants is
// one tree when it has any; a "tree_" node alone has no hierarchy to sway and stays static.
std::vector<int> treeOfNodes(const std::vector<MeshNode>& nodes, int& count) {
    std::vector<int> tree(nodes.size(), -1);
    std::vector<std::size_t> size;
    for (std::size_t i = 0; i < nodes.size(); ++i) {
        if (!isTreeNode(nodes[i])) continue;
        const int parent = nodes[i].parent;
        tree[i] = parent >= 0 && tree[std::size_t(parent)] >= 0 ? tree[std::size_t(parent)] : int(size.size());
        if (tree[i] == int(size.size())) size.push_back(0);
        ++size[std::size_t(tree[i])];
    }
    std::vector<int> renumber(size.size(), -1);
    count = 0;
    for (std::size_t t = 0; t < size.size(); ++t)
        if (size[t] > 1) renumber[t] = count++;
    for (int& t : tree) t = t >= 0 ? renumber[std::size_t(t)] : -1;
    return tree;
}

// Splits `nodes` into the trees' nodes (moved to `trees`, each tree's trunk first) and the
// rest, parents renumbered within each list (a parent in the other list becomes -1).
std::vector<TreeNodes> takeTrees(std::vector<MeshNode>& nodes, std::vector<MeshNode>& trees) {
    int count = 0;
    const std::vector<int> tree = treeOfNodes(nodes, count);
    std::vector<TreeNodes> out(static_cast<std::size_t>(count));
    std::vector<MeshNode> rest;
    std::vector<int> newIndex(nodes.size(), -1);
    for (std::size_t i = 0; i < nodes.size(); ++i) {
        std::vector<MeshNode>& list = tree[i] < 0 ? rest : trees;
        if (tree[i] >= 0) out[std::size_t(tree[i])].nodes.push_back(trees.size());
        newIndex[i] = int(list.size());
        list.push_back(std::move(nodes[i]));
    }
    const auto renumber = [&](MeshNode& n, bool inTree) {
        const bool sameList = n.parent >= 0 && (tree[std::size_t(n.parent)] >= 0) == inTree;
        n.parent = sameList ? newIndex[std::size_t(n.parent)] : -1;
    };
    for (MeshNode& n : trees) renumber(n, true);
    for (MeshNode& n : rest) renumber(n, false);
    nodes = std::move(rest);
    return out;
}

// Trees showing the same meshes are one species: each species' trees, in file order.
std::vector<std::vector<std::size_t>> groupSpecies(const std::vector<MeshNode>& nodes, const std::vector<TreeNodes>& trees) {
    std::vector<std::vector<std::size_t>> members;
    for (std::size_t t = 0; t < trees.size(); ++t) {
        std::size_t s = 0;
        while (s < members.size() && !sameSpecies(nodes, trees[members[s][0]], trees[t])) ++s;
        if (s == members.size()) members.emplace_back();
        members[s].push_back(t);
    }
    return members;
}

}  // namespace

PivotTextures uploadPivotTextures(const exporters::PivotPainter& painter) {
    PivotTextures t;
    const auto upload = [&](const std::vector<float>& texels) {
        gl::Texture tex = gl::makeTexture2D(GL_RGBA32F, painter.width, painter.height, 1, GL_NEAREST, GL_NEAREST, GL_CLAMP_TO_EDGE);
        glTextureSubImage2D(tex.id(), 0, 0, 0, painter.width, painter.height, GL_RGBA, GL_FLOAT, texels.data());
        return tex;
    };
    t.pivots = upload(painter.pivots);
    t.axes = upload(painter.axes);
    return t;
}

std::size_t TreeCpu::bytes() const {
    std::size_t n = vertices.size() * sizeof(StaticVertex) + indices.size() * 4 + instances.size() * sizeof(TreeInstance);
    for (const Species& sp : species) n += (sp.painter.pivots.size() + sp.painter.axes.size()) * sizeof(float);
    return n;
}

TreeCpu prepareTrees(std::vector<MeshNode>& nodes, glm::uvec4 blocks, glm::dvec3& lo, glm::dvec3& hi) {
    TreeCpu out;
    std::vector<MeshNode> treeNodes;
    const std::vector<TreeNodes> trees = takeTrees(nodes, treeNodes);
    out.trees = trees.size();
    if (trees.empty()) return out;
    const std::vector<std::vector<std::size_t>> members = groupSpecies(treeNodes, trees);
    for (std::size_t s = 0; s < members.size(); ++s) {
        const TreeNodes& first = trees[members[s][0]];
        TreeCpu::Species sp;
        sp.painter = exporters::buildPivotPainter(treeSpaceNodes(treeNodes, first), exporters::PivotPreset::Native,
                                                  treeNodes[first.nodes[0]].name);
        const Mesh& mesh = sp.painter.mesh;
        sp.firstIndex = std::uint32_t(out.indices.size());
        sp.indexCount = std::uint32_t(mesh.indices.size());
        sp.baseVertex = std::uint32_t(out.vertices.size());
        sp.firstInstance = std::uint32_t(out.instances.size());
        sp.instances = std::uint32_t(members[s].size());
        for (std::size_t i = 0; i < mesh.positions.size(); ++i)
            out.vertices.push_back(staticVertex(mesh, i, glm::mat4(1.0f), glm::mat3(1.0f)));
        out.indices.insert(out.indices.end(), mesh.indices.begin(), mesh.indices.end());
        const Bounds box = computeBounds(mesh.positions);
        for (std::size_t t : members[s]) {
            const glm::mat4& model = treeNodes[trees[t].nodes[0]].world;
            out.instances.push_back({model, blocks, 0xffffu, {0, 0, 0}});
            glm::dvec3 tlo(std::numeric_limits<double>::max()), thi(-std::numeric_limits<double>::max());
            growPlacedBox(box.min, box.max, model, tlo, thi);
            // Swaying moves the crown by well under a metre: a metre of margin.
            out.boxMin.push_back(glm::vec3(tlo) - 1.0f);
            out.boxMax.push_back(glm::vec3(thi) + 1.0f);
            lo = glm::min(lo, tlo), hi = glm::max(hi, thi);
        }
        sp.painter.mesh = Mesh{};  // in `vertices` now
        out.species.push_back(std::move(sp));
    }
    return out;
}

void TreePrograms::make() {
    surface = gl::makeProgram("tree.vert", "surface.frag", {"TREE"});
    depth = gl::makeProgram("tree.vert", "depth.frag", {"DEPTH_PASS", "TREE"});
    const LeafImage image = makeLeafImage();
    leaves = gl::makeTexture2D(GL_SRGB8_ALPHA8, kLeafSize, kLeafSize, kLeafLevels, GL_LINEAR_MIPMAP_LINEAR, GL_LINEAR, GL_CLAMP_TO_EDGE);
    for (int l = 0; l < kLeafLevels; ++l)
        glTextureSubImage2D(leaves.id(), l, 0, 0, kLeafSize >> l, kLeafSize >> l, GL_RGBA, GL_UNSIGNED_BYTE, image.rgba[std::size_t(l)].data());
}

void TreeGpu::upload(const TreeCpu& cpu) {
    treeCount_ = cpu.trees;
    if (cpu.species.empty()) return;
    for (const TreeCpu::Species& s : cpu.species)
        species_.push_back({uploadPivotTextures(s.painter), s.firstIndex, s.indexCount, s.baseVertex, s.firstInstance, s.instances});
    vertices_ = gl::makeBuffer(cpu.vertices);
    indices_ = gl::makeBuffer(cpu.indices);
    instances_ = gl::makeBuffer(nullptr, cpu.instances.size() * sizeof(TreeInstance), GL_DYNAMIC_STORAGE_BIT);
    all_ = cpu.instances;
    boxMin_ = cpu.boxMin, boxMax_ = cpu.boxMax;
    vao_ = gl::makeVertexArray();
    const GLuint vao = vao_.id();
    instancedLayout(vao, vertices_.id(), indices_.id(), instances_.id(), sizeof(TreeInstance), offsetof(TreeInstance, blocks),
                    offsetof(TreeInstance, building));
    // The model matrix: attributes 10-13, one column each.
    for (GLuint c = 0; c < 4; ++c) {
        glVertexArrayAttribFormat(vao, 10 + c, 4, GL_FLOAT, GL_FALSE, GLuint(offsetof(TreeInstance, model) + c * sizeof(glm::vec4)));
        glEnableVertexArrayAttrib(vao, 10 + c);
        glVertexArrayAttribBinding(vao, 10 + c, 1);
    }
}

std::size_t TreeGpu::draw(const TreePrograms& programs, const WindSettings& wind, double time, const glm::mat4& viewProj,
                          bool depth, glm::vec3 offset, FrameStats* stats) {
    if (species_.empty()) return 0;
    // The visible trees of each species, packed: each species draws its run of them.
    visible_.clear();
    std::vector<std::pair<std::uint32_t, std::uint32_t>> runs;  // first visible instance, count
    for (const Species& s : species_) {
        const std::uint32_t first = std::uint32_t(visible_.size());
        for (std::uint32_t i = s.firstInstance; i < s.firstInstance + s.instances; ++i)
            if (!outsideFrustum(viewProj, boxMin_[i] + offset, boxMax_[i] + offset)) visible_.push_back(all_[i]);
        runs.emplace_back(first, std::uint32_t(visible_.size()) - first);
    }
    if (visible_.empty()) return 0;
    glNamedBufferSubData(instances_.id(), 0, GLsizeiptr(visible_.size() * sizeof(TreeInstance)), visible_.data());
    glUseProgram(depth ? programs.depth.id() : programs.surface.id());
    if (depth) glUniformMatrix4fv(0, 1, GL_FALSE, glm::value_ptr(viewProj));
    const glm::vec3 d(wind.direction);
    glUniform4f(5, d.x, d.y, d.z, float(wind.speed));
    glUniform1f(6, float(time));
    glUniform3f(8, offset.x, offset.y, offset.z);
    glBindTextureUnit(kLeafUnit, programs.leaves.id());
    glBindVertexArray(vao_.id());
    std::size_t draws = 0;
    for (std::size_t k = 0; k < species_.size(); ++k) {
        const Species& s = species_[k];
        if (runs[k].second == 0) continue;
        glBindTextureUnit(kPivotUnit, s.textures.pivots.id());
        glBindTextureUnit(kAxisUnit, s.textures.axes.id());
        glDrawElementsInstancedBaseVertexBaseInstance(GL_TRIANGLES, GLsizei(s.indexCount), GL_UNSIGNED_INT,
                                                      reinterpret_cast<const void*>(std::uintptr_t(s.firstIndex) * 4u),
                                                      GLsizei(runs[k].second), GLint(s.baseVertex), runs[k].first);
        if (stats) stats->triangles += std::size_t(s.indexCount / 3) * runs[k].second;
        ++draws;
    }
    return draws;
}

}  // namespace dawnforge::runtime
