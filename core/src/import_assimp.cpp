// Mesh import through Assimp 5.2 (Debian's libassimp-dev): every format it reads except
// OBJ and glTF, which tinyobjloader and tinygltf read (import.cpp), and OFF, which CGAL
// reads (import_off.cpp).
//
// Units and axes: dawnforge is metres, +Y up, right-handed (glTF). What Assimp 5.2.5
// already does, read in its source (github.com/assimp/assimp, tag v5.2.5) and checked on
// the files of Debian's assimp-testmodels:
// - FBX: code/AssetLib/FBX/FBXConverter.cpp (ConvertGlobalSettings) copies the file's
//   GlobalSettings into scene->mMetaData (UpAxis, UpAxisSign, FrontAxis, FrontAxisSign,
//   CoordAxis, CoordAxisSign as int32; UnitScaleFactor, centimetres per file unit, as
//   float) and changes no coordinate: vertices and node transforms stay in the file's
//   units and axes (spider.fbx, UnitScaleFactor 1, reads 100 times spider.obj). FBXImporter.cpp
//   calls SetFileScale(UnitScaleFactor * 0.01), which only aiProcess_GlobalScale
//   (code/PostProcessing/ScaleProcess.cpp) applies, through AI_CONFIG_APP_SCALE_KEY
//   times AI_CONFIG_GLOBAL_SCALE_FACTOR_KEY; that step rebuilds every node matrix as
//   translation x rotation x scale, which drops the shear a non-uniformly scaled parent
//   gives a rotated child. AI_CONFIG_FBX_CONVERT_TO_M is read into the importer's settings
//   and used nowhere. No setting converts axes. So this file leaves aiProcess_GlobalScale
//   off and puts the unit scale and the axis change into the root transform itself
//   (fbxToDawnforge below).
// - Collada: code/AssetLib/Collada/ColladaLoader.cpp (InternReadFile) multiplies the root
//   node by <unit meter> and, unless AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION is set,
//   rotates X_UP and Z_UP to +Y up (cube_with_2UVs.DAE, inches and Z_UP, reads 0.0508 m
//   tall in +Y). Nothing is left to do.
// - 3DS: code/AssetLib/3DS/3DSConverter.cpp rotates Z up to Y up at the root, and
//   3DSLoader.cpp (ApplyMasterScale) scales the root by 1 / the master scale. Taken as
//   metres after that.
// - STL, PLY and the rest carry no unit: their coordinates are taken as metres, with
//   the axes as they are.
#include "import_assimp.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>

#include <assimp/Importer.hpp>
#include <assimp/commonMetaData.h>
#include <assimp/config.h>
#include <assimp/importerdesc.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <glm/gtc/matrix_transform.hpp>

#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iostream>
#include <limits>
#include <mutex>
#include <optional>
#include <streambuf>
#include <utility>

namespace dawnforge::detail {

namespace fs = std::filesystem;

namespace {

glm::mat4 toGlm(const aiMatrix4x4& m) {
    // aiMatrix4x4 is row-major (a1 a2 a3 a4 is the first row); glm takes columns.
    return glm::mat4(m.a1, m.b1, m.c1, m.d1, m.a2, m.b2, m.c2, m.d2, m.a3, m.b3, m.c3, m.d3, m.a4, m.b4, m.c4,
                     m.d4);
}

std::optional<double> metadataNumber(const aiMetadata* meta, const char* key) {
    if (meta == nullptr) return std::nullopt;
    for (unsigned i = 0; i < meta->mNumProperties; ++i) {
        if (std::strcmp(meta->mKeys[i].C_Str(), key) != 0) continue;
        const aiMetadataEntry& e = meta->mValues[i];
        if (e.mData == nullptr) return std::nullopt;
        switch (e.mType) {
            case AI_INT32: return double(*static_cast<const std::int32_t*>(e.mData));
            case AI_UINT64: return double(*static_cast<const std::uint64_t*>(e.mData));
            case AI_FLOAT: return double(*static_cast<const float*>(e.mData));
            case AI_DOUBLE: return *static_cast<const double*>(e.mData);
            default: return std::nullopt;
        }
    }
    return std::nullopt;
}

std::string metadataString(const aiMetadata* meta, const char* key) {
    aiString value;
    if (meta == nullptr || !meta->Get(key, value)) return {};
    return value.C_Str();
}

// The transform from an FBX file's axes and units to dawnforge's. The file's right, up
// and front (towards the viewer) vectors are sign * axis (CoordAxis, UpAxis, FrontAxis:
// 0 = X, 1 = Y, 2 = Z); they become +X, +Y and +Z, so Maya's default (X, Y, Z) is the
// identity and 3ds Max's (X, Z, -Y) takes (x, y, z) to (x, z, -y). A left-handed file
// gives a mirroring matrix, whose winding appendMesh restores. FBX's defaults (Y up,
// centimetres) stand for a missing entry.
glm::mat4 fbxToDawnforge(const aiMetadata* meta, const std::string& name) {
    auto entry = [&](const char* key, double fallback) { return metadataNumber(meta, key).value_or(fallback); };
    const std::array<std::pair<const char*, const char*>, 3> keys{
        {{"CoordAxis", "CoordAxisSign"}, {"UpAxis", "UpAxisSign"}, {"FrontAxis", "FrontAxisSign"}}};
    const std::array<double, 3> defaultAxis{0, 1, 2};
    glm::mat4 axes(0.0f);
    axes[3][3] = 1.0f;
    std::array<bool, 3> used{};
    for (std::size_t row = 0; row < 3; ++row) {
        const double axis = entry(keys[row].first, defaultAxis[row]);
        const double sign = entry(keys[row].second, 1.0);
        if (!(axis == 0 || axis == 1 || axis == 2) || used[std::size_t(axis)] || !(sign == 1 || sign == -1))
            throw InputError(format("{}: the FBX axis system is invalid ({} {}, {} {})", name, keys[row].first, axis,
                                    keys[row].second, sign));
        used[std::size_t(axis)] = true;
        axes[int(axis)][int(row)] = float(sign);  // row `row` of the matrix picks that file axis
    }
    const double unit = entry("UnitScaleFactor", 1.0);
    if (!std::isfinite(unit) || unit <= 0.0)
        throw InputError(format("{}: the FBX UnitScaleFactor ({}) is not a positive number", name, unit));
    const float metres = float(unit * 0.01);  // UnitScaleFactor is centimetres per file unit
    return glm::scale(glm::mat4(1.0f), glm::vec3(metres)) * axes;
}

// One Assimp mesh as a core Mesh: positions, normals and the first UV set; triangles only
// (points and lines, which Assimp keeps in faces of one or two corners, are skipped).
Mesh readMesh(const aiMesh& in, const std::string& name) {
    Mesh mesh;
    if (in.mVertices == nullptr) return mesh;
    mesh.positions.reserve(in.mNumVertices);
    for (unsigned v = 0; v < in.mNumVertices; ++v)
        mesh.positions.emplace_back(in.mVertices[v].x, in.mVertices[v].y, in.mVertices[v].z);
    if (in.mNormals != nullptr)
        for (unsigned v = 0; v < in.mNumVertices; ++v)
            mesh.normals.emplace_back(in.mNormals[v].x, in.mNormals[v].y, in.mNormals[v].z);
    if (in.mTextureCoords[0] != nullptr)
        for (unsigned v = 0; v < in.mNumVertices; ++v)
            mesh.uv0.emplace_back(in.mTextureCoords[0][v].x, in.mTextureCoords[0][v].y);
    if (in.mFaces == nullptr) return mesh;
    mesh.indices.reserve(std::size_t(in.mNumFaces) * 3);
    for (unsigned f = 0; f < in.mNumFaces; ++f) {
        const aiFace& face = in.mFaces[f];
        if (face.mNumIndices != 3 || face.mIndices == nullptr) continue;
        for (unsigned c = 0; c < 3; ++c) {
            if (face.mIndices[c] >= in.mNumVertices)
                throw InputError(format("{}: a face of mesh '{}' uses vertex {} but the mesh has {} vertices", name,
                                        in.mName.C_Str(), face.mIndices[c], in.mNumVertices));
            mesh.indices.push_back(face.mIndices[c]);
        }
    }
    return mesh;
}

// Some of Assimp 5.2's readers write to std::cerr themselves (the OpenDDL parser under
// OpenGEX: "nullptr returned by creating DDLNode."; the MMD reader), where the CLI's
// one-line error and inspect's JSON go. Their output is dropped while Assimp reads; the
// mutex keeps two imports from swapping the buffers at once.
class QuietStreams {
public:
    QuietStreams() : lock_(mutex()), out_(std::cout.rdbuf(&null_)), err_(std::cerr.rdbuf(&null_)) {}
    ~QuietStreams() {
        std::cout.rdbuf(out_);
        std::cerr.rdbuf(err_);
    }
    QuietStreams(const QuietStreams&) = delete;
    QuietStreams& operator=(const QuietStreams&) = delete;

private:
    struct NullBuffer : std::streambuf {
        int overflow(int c) override { return traits_type::not_eof(c); }
    };
    static std::mutex& mutex() {
        static std::mutex m;
        return m;
    }
    std::lock_guard<std::mutex> lock_;
    NullBuffer null_;
    std::streambuf* out_;
    std::streambuf* err_;
};

}  // namespace

bool assimpReadsExtension(std::string_view extension) {
    const Assimp::Importer importer;
    return !extension.empty() && importer.IsExtensionSupported(std::string(extension));
}

std::vector<MeshNode> loadAssimpNodes(const fs::path& file, const std::string& name) {
    Assimp::Importer importer;
    // Geometry only: what is dropped before JoinIdenticalVertices lets it join more.
    importer.SetPropertyInteger(AI_CONFIG_PP_RVC_FLAGS,
                                aiComponent_COLORS | aiComponent_TANGENTS_AND_BITANGENTS | aiComponent_BONEWEIGHTS |
                                    aiComponent_ANIMATIONS | aiComponent_TEXTURES | aiComponent_LIGHTS |
                                    aiComponent_CAMERAS);
    importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
    // Node transforms are applied here (as for glTF), not by aiProcess_PreTransformVertices,
    // so that loadMeshNodes can give each node its own.
    const unsigned steps = aiProcess_ValidateDataStructure | aiProcess_RemoveComponent | aiProcess_Triangulate |
                           aiProcess_SortByPType | aiProcess_JoinIdenticalVertices;
    const aiScene* scene = nullptr;
    {
        const QuietStreams quiet;
        scene = importer.ReadFile(file.string(), steps);
    }
    if (scene == nullptr || scene->mRootNode == nullptr) {
        const std::string why = oneLine(importer.GetErrorString());
        throw InputError(format("{}: not a readable mesh file: {}", name, why.empty() ? "no scene" : why));
    }

    glm::mat4 root(1.0f);
    const aiImporterDesc* fbx = importer.GetImporterInfo(importer.GetImporterIndex(".fbx"));
    if (fbx != nullptr && metadataString(scene->mMetaData, AI_METADATA_SOURCE_FORMAT) == fbx->mName)
        root = fbxToDawnforge(scene->mMetaData, name);

    // Depth first, children in order, without recursion (a malformed file may nest deeply).
    std::vector<MeshNode> nodes;
    struct Pending {
        const aiNode* node;
        glm::mat4 parent;
        int parentEntry;  // the nearest ancestor entry that shows a mesh
    };
    std::vector<Pending> stack{{scene->mRootNode, root, -1}};
    while (!stack.empty()) {
        auto [node, parent, parentEntry] = stack.back();
        stack.pop_back();
        const glm::mat4 world = parent * toGlm(node->mTransformation);
        if (node->mNumMeshes > 0 && node->mMeshes != nullptr) {
            MeshNode entry;
            entry.name = node->mName.C_Str();
            entry.world = world;
            entry.parent = parentEntry;
            entry.mesh.name = entry.name;
            for (unsigned i = 0; i < node->mNumMeshes; ++i) {
                const unsigned m = node->mMeshes[i];
                if (m >= scene->mNumMeshes || scene->mMeshes[m] == nullptr)
                    throw InputError(format("{}: node '{}' refers to mesh {} which does not exist", name,
                                            entry.name, m));
                appendMesh(entry.mesh, readMesh(*scene->mMeshes[m], name));
            }
            parentEntry = int(nodes.size());
            nodes.push_back(std::move(entry));
        }
        if (node->mChildren != nullptr)
            for (unsigned c = node->mNumChildren; c-- > 0;)
                if (node->mChildren[c] != nullptr) stack.push_back({node->mChildren[c], world, parentEntry});
    }
    return nodes;
}

}  // namespace dawnforge::detail
