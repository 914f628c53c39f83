#include "mesh_wire.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>

#include <cstdint>
#include <type_traits>

namespace dawnforge::detail {

namespace {

constexpr std::uint32_t kMagic = 0x4E4D4644;  // "DFMN"

// Writes, or only counts, the bytes of `nodes` (one function for both, so they cannot differ).
template <typename Out>
void put(const std::vector<MeshNode>& nodes, Out& out) {
    auto value = [&](const auto& v) {
        static_assert(std::is_trivially_copyable_v<std::decay_t<decltype(v)>>);
        out(&v, sizeof v);
    };
    auto array = [&](const auto& v) {
        value(std::uint64_t(v.size()));
        out(v.data(), v.size() * sizeof v[0]);
    };
    value(kMagic);
    value(std::uint64_t(nodes.size()));
    for (const MeshNode& n : nodes) {
        array(n.name);
        value(n.world);
        value(std::int32_t(n.parent));
        const Mesh& m = n.mesh;
        array(m.name);
        array(m.positions);
        array(m.indices);
        array(m.normals);
        for (const auto* uv : {&m.uv0, &m.uv1, &m.uv2, &m.uv3}) array(*uv);
        array(m.materialIds);
        array(m.pieceIds);
    }
}

class Reader {
public:
    Reader(AnswerSource& source, const std::string& name) : source_(source), name_(name) {}

    template <typename T>
    T value() {
        T v;
        source_.read(&v, sizeof v);
        return v;
    }
    template <typename Container>
    void array(Container& v, const char* what) {
        const std::uint64_t n = value<std::uint64_t>();
        if (n > source_.left() / sizeof v[0]) damaged(format("{} {} claimed, {} bytes left", n, what, source_.left()));
        v.resize(n);
        source_.read(v.data(), n * sizeof v[0]);
    }
    [[noreturn]] void damaged(const std::string& why) const {
        throw InputError(format("{}: the reader's answer is damaged ({})", name_, why));
    }

private:
    AnswerSource& source_;
    const std::string& name_;
};

}  // namespace

Answer encodeNodes(std::shared_ptr<const std::vector<MeshNode>> nodes) {
    Answer answer;
    auto count = [&answer](const void*, std::size_t size) { answer.size += size; };
    put(*nodes, count);
    answer.write = [nodes](AnswerSink& sink) {
        auto write = [&sink](const void* data, std::size_t size) { sink.write(data, size); };
        put(*nodes, write);
    };
    return answer;
}

std::vector<MeshNode> decodeNodes(AnswerSource& source, const std::string& name) {
    Reader r(source, name);
    if (r.value<std::uint32_t>() != kMagic) r.damaged("no magic number");
    const std::uint64_t count = r.value<std::uint64_t>();
    if (count > source.left()) r.damaged(format("{} nodes claimed", count));
    std::vector<MeshNode> nodes(count);
    for (std::size_t i = 0; i < nodes.size(); ++i) {
        MeshNode& n = nodes[i];
        r.array(n.name, "name bytes");
        n.world = r.value<glm::mat4>();
        n.parent = r.value<std::int32_t>();
        if (n.parent < -1 || n.parent >= std::int32_t(i)) r.damaged(format("node {} has parent {}", i, n.parent));
        Mesh& m = n.mesh;
        r.array(m.name, "name bytes");
        r.array(m.positions, "positions");
        r.array(m.indices, "indices");
        r.array(m.normals, "normals");
        for (auto* uv : {&m.uv0, &m.uv1, &m.uv2, &m.uv3}) r.array(*uv, "UVs");
        r.array(m.materialIds, "material IDs");
        r.array(m.pieceIds, "piece IDs");
    }
    return nodes;
}

}  // namespace dawnforge::detail
