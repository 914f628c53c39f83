// Probe placement and cache (probe_placement.hpp).
#include <dawnforge/runtime/probe_placement.hpp>

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>

namespace dawnforge::runtime {

namespace {

constexpr int kKeyBits = 21;
constexpr std::int64_t kKeyOffset = std::int64_t(1) << (kKeyBits - 1);
constexpr std::uint64_t kKeyMask = (std::uint64_t(1) << kKeyBits) - 1;

std::uint64_t columnKey(std::int64_t x, std::int64_t z) { return (std::uint64_t(x) << 32) ^ std::uint64_t(std::uint32_t(z)); }

// p in the box's frame: (along u, up, along w).
glm::dvec3 local(const ProbeBox& b, glm::dvec3 p) {
    const glm::dvec3 d = p - b.centre;
    return {glm::dot(d, b.u), d.y, glm::dot(d, b.w)};
}

// The box's half extent along world x and z.
glm::dvec2 planExtent(const ProbeBox& b) {
    return {std::abs(b.u.x) * b.halfSize.x + std::abs(b.w.x) * b.halfSize.z,
            std::abs(b.u.z) * b.halfSize.x + std::abs(b.w.z) * b.halfSize.z};
}

}  // namespace

std::optional<ProbePreset> probePreset(std::string_view name) {
    if (name == "low") return ProbePreset{"low", ProbeBasis::AmbientCube, 150.0, 256, 4.0};
    if (name == "mid") return ProbePreset{"mid", ProbeBasis::AmbientCube, 300.0, 512, 2.0};
    if (name == "high") return ProbePreset{"high", ProbeBasis::Sh, 600.0, 256, 1.0};
    return std::nullopt;
}

std::vector<ProbeBox> parseProbeBoxes(const std::string& json, const std::string& source) {
    std::vector<ProbeBox> boxes;
    try {
        const nlohmann::json j = nlohmann::json::parse(json);
        if (j.at("format") != "dawnforge.proxies") throw InputError(format("{}: not a dawnforge.proxies document", source));
        const auto vec = [](const nlohmann::json& v) { return glm::dvec3(v.at(0).get<double>(), v.at(1).get<double>(), v.at(2).get<double>()); };
        for (const nlohmann::json& b : j.at("boxes")) {
            ProbeBox box;
            box.centre = vec(b.at("centre"));
            box.u = vec(b.at("u"));
            box.w = vec(b.at("w"));
            box.halfSize = vec(b.at("half_size"));
            const std::string name = b.at("name").get<std::string>();
            if (name.starts_with("building_") && name.size() > 9 && std::isdigit(static_cast<unsigned char>(name[9])))
                box.building = std::atoi(name.c_str() + 9);
            const std::string kind = b.at("kind").get<std::string>();
            box.ground = kind == "ground" || kind == "kerb" || kind == "street";
            const nlohmann::json& colours = b.at("colours");
            if (colours.size() != 6) throw InputError(format("{}: a box needs 6 face colours", source));
            for (int f = 0; f < 6; ++f) box.colours[std::size_t(f)] = glm::vec3(vec(colours.at(std::size_t(f))));
            boxes.push_back(box);
        }
    } catch (const nlohmann::json::exception& e) {
        throw InputError(format("{}: {}", source, oneLine(e.what())));
    }
    return boxes;
}

ProbeKey probeKey(glm::ivec3 lattice) {
    ProbeKey key = 0;
    for (int a = 0; a < 3; ++a) key |= (std::uint64_t(std::int64_t(lattice[a]) + kKeyOffset) & kKeyMask) << (kKeyBits * a);
    return key;
}

glm::ivec3 probeLattice(ProbeKey key) {
    glm::ivec3 l;
    for (int a = 0; a < 3; ++a) l[a] = int(std::int64_t((key >> (kKeyBits * a)) & kKeyMask) - kKeyOffset);
    return l;
}

ProbeField::ProbeField(std::vector<ProbeBox> boxes, double cell) : boxes_(std::move(boxes)), cell_(cell) {
    for (std::uint32_t i = 0; i < boxes_.size(); ++i) {
        const glm::dvec2 e = planExtent(boxes_[i]), c(boxes_[i].centre.x, boxes_[i].centre.z);
        const auto x0 = std::int64_t(std::floor((c.x - e.x) / cell_)), x1 = std::int64_t(std::floor((c.x + e.x) / cell_));
        const auto z0 = std::int64_t(std::floor((c.y - e.y) / cell_)), z1 = std::int64_t(std::floor((c.y + e.y) / cell_));
        for (std::int64_t x = x0; x <= x1; ++x)
            for (std::int64_t z = z0; z <= z1; ++z) columns_[columnKey(x, z)].push_back(i);
    }
}

std::vector<std::uint32_t> ProbeField::candidates(glm::dvec3 p, double reach) const {
    std::vector<std::uint32_t> out;
    const auto x0 = std::int64_t(std::floor((p.x - reach) / cell_)), x1 = std::int64_t(std::floor((p.x + reach) / cell_));
    const auto z0 = std::int64_t(std::floor((p.z - reach) / cell_)), z1 = std::int64_t(std::floor((p.z + reach) / cell_));
    for (std::int64_t x = x0; x <= x1; ++x)
        for (std::int64_t z = z0; z <= z1; ++z) {
            const auto it = columns_.find(columnKey(x, z));
            if (it != columns_.end()) out.insert(out.end(), it->second.begin(), it->second.end());
        }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

bool ProbeField::inside(glm::dvec3 p) const {
    for (std::uint32_t i : candidates(p, 0.0)) {
        const glm::dvec3 l = local(boxes_[i], p), h = boxes_[i].halfSize;
        const bool below = boxes_[i].ground ? l.y < h.y : std::abs(l.y) < h.y;
        if (std::abs(l.x) < h.x && below && std::abs(l.z) < h.z) return true;
    }
    return false;
}

bool ProbeField::near(glm::dvec3 p, double reach) const {
    for (std::uint32_t i : candidates(p, reach)) {
        const glm::dvec3 l = local(boxes_[i], p);
        if (glm::length(l - glm::clamp(l, -boxes_[i].halfSize, boxes_[i].halfSize)) <= reach) return true;
    }
    return false;
}

std::vector<PlacedProbe> ProbeField::place(glm::dvec3 camera, glm::dvec3 halfExtent, double spacing) const {
    const glm::ivec3 lo(glm::ceil((camera - halfExtent) / spacing - 0.5)), hi(glm::floor((camera + halfExtent) / spacing - 0.5));
    std::vector<PlacedProbe> out;
    for (int k = lo.y; k <= hi.y; ++k)
        for (int j = lo.z; j <= hi.z; ++j)
            for (int i = lo.x; i <= hi.x; ++i) {
                const glm::dvec3 p = spacing * (glm::dvec3(i, k, j) + 0.5);
                if (near(p, spacing) && !inside(p)) out.push_back({probeKey({i, k, j}), p});
            }
    std::sort(out.begin(), out.end(), [&](const PlacedProbe& a, const PlacedProbe& b) {
        const double da = glm::dot(a.position - camera, a.position - camera), db = glm::dot(b.position - camera, b.position - camera);
        return da != db ? da < db : a.key < b.key;
    });
    return out;
}

ProbeCache::ProbeCache(int capacity) : capacity_(std::max(capacity, 0)) {
    for (int slot = capacity_ - 1; slot >= 0; --slot) free_.push_back(slot);
}

int ProbeCache::slotOf(ProbeKey key) const {
    const auto it = held_.find(key);
    return it == held_.end() ? -1 : it->second.slot;
}

std::vector<PlacedProbe> ProbeCache::admit(std::span<const PlacedProbe> wanted, glm::dvec3 camera, int budget) {
    std::vector<PlacedProbe> admitted;
    for (const PlacedProbe& p : wanted) {
        if (int(admitted.size()) >= budget || capacity_ <= 0) break;
        if (held_.count(p.key)) continue;
        if (int(held_.size()) >= capacity_) {
            // The farthest from the camera goes (ties by key, so the same choice every run).
            auto farthest = held_.begin();
            for (auto it = held_.begin(); it != held_.end(); ++it) {
                const double d = glm::length(it->second.position - camera), f = glm::length(farthest->second.position - camera);
                if (d > f || (d == f && it->first > farthest->first)) farthest = it;
            }
            if (glm::length(farthest->second.position - camera) <= glm::length(p.position - camera)) break;  // nothing worse to drop
            free_.push_back(farthest->second.slot);
            held_.erase(farthest);
        }
        PlacedProbe placed = p;
        placed.slot = free_.back();
        free_.pop_back();
        held_.emplace(p.key, Held{p.position, placed.slot});
        admitted.push_back(placed);
    }
    return admitted;
}

}  // namespace dawnforge::runtime
