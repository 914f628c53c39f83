// Flat-coloured proxy boxes (proxies.hpp).
#include <dawnforge/bake/proxies.hpp>
#include <dawnforge/bake/lighting.hpp>
#include "plane_geometry.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/materials.hpp>

#include <nlohmann/json.hpp>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>
#include <tuple>

namespace dawnforge::bake {

namespace {

constexpr double kMinFill = 0.7;  // a box less full than this (plan hull / rectangle) is cut in two

std::uint32_t findRoot(std::vector<std::uint32_t>& parent, std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
}

// Connected parts of a mesh (triangles joined through welded corners), each a sorted list of
// triangles, in order of their first triangle.
std::vector<std::vector<std::uint32_t>> parts(const Mesh& m) {
    using Key = std::tuple<long long, long long, long long>;
    std::map<Key, std::uint32_t> firstTriangle;
    const std::size_t nt = m.triangleCount();
    std::vector<std::uint32_t> parent(nt);
    std::iota(parent.begin(), parent.end(), 0u);
    for (std::uint32_t t = 0; t < nt; ++t)
        for (int k = 0; k < 3; ++k) {
            const glm::vec3 p = m.positions[m.indices[3 * std::size_t(t) + std::size_t(k)]];
            const Key key{std::llround(p.x * 1e4), std::llround(p.y * 1e4), std::llround(p.z * 1e4)};
            auto [it, added] = firstTriangle.try_emplace(key, t);
            if (!added) {
                const std::uint32_t a = findRoot(parent, it->second), b = findRoot(parent, t);
                if (a != b) parent[std::max(a, b)] = std::min(a, b);
            }
        }
    std::map<std::uint32_t, std::vector<std::uint32_t>> groups;
    for (std::uint32_t t = 0; t < nt; ++t) groups[findRoot(parent, t)].push_back(t);
    std::vector<std::vector<std::uint32_t>> out;
    for (auto& [root, tris] : groups) out.push_back(std::move(tris));
    return out;
}

glm::dvec3 corner(const Mesh& m, std::uint32_t t, int k) { return glm::dvec3(m.positions[m.indices[3 * std::size_t(t) + std::size_t(k)]]); }

std::uint8_t materialOf(const Mesh& m, std::uint32_t t) {
    return m.materialIds.empty() ? std::uint8_t{0} : std::uint8_t(m.materialIds[m.indices[3 * std::size_t(t)]] & 15u);
}

struct PlanBox {
    glm::dvec2 u{1, 0}, w{0, 1};  // plan (x, z) axes
    glm::dvec2 lo{0.0}, hi{0.0};  // extent along them
};

PlanBox fitPlan(const std::vector<glm::dvec2>& hull) {
    const double angle = minAreaRectAngle(hull);
    PlanBox b;
    b.u = {std::cos(angle), std::sin(angle)};
    b.w = {-std::sin(angle), std::cos(angle)};
    b.lo = glm::dvec2(INFINITY), b.hi = glm::dvec2(-INFINITY);
    for (const glm::dvec2& p : hull) {
        const glm::dvec2 q(glm::dot(p, b.u), glm::dot(p, b.w));
        b.lo = glm::min(b.lo, q), b.hi = glm::max(b.hi, q);
    }
    return b;
}

double polygonArea(const std::vector<glm::dvec2>& poly) {
    double a = 0.0;
    for (std::size_t i = 0; i < poly.size(); ++i) a += cross2(poly[i], poly[(i + 1) % poly.size()]);
    return 0.5 * std::abs(a);
}

// The part of a convex polygon where dot(p, axis) <= cut (keep = -1) or >= cut (keep = +1).
std::vector<glm::dvec2> clip(const std::vector<glm::dvec2>& poly, glm::dvec2 axis, double cut, double keep) {
    std::vector<glm::dvec2> out;
    for (std::size_t i = 0; i < poly.size(); ++i) {
        const glm::dvec2 a = poly[i], b = poly[(i + 1) % poly.size()];
        const double da = keep * (glm::dot(a, axis) - cut), db = keep * (glm::dot(b, axis) - cut);
        if (da >= 0.0) out.push_back(a);
        if ((da >= 0.0) != (db >= 0.0)) out.push_back(a + (b - a) * (da / (da - db)));
    }
    return out;
}

// One colour per face from the triangles, each adding its area projected on every face it looks towards.
void colourFaces(ProxyBox& box, const Mesh& m, const std::vector<std::uint32_t>& tris) {
    const glm::dvec3 faces[6] = {box.u, -box.u, {0, 1, 0}, {0, -1, 0}, box.w, -box.w};
    glm::dvec3 sum[6] = {};
    double weight[6] = {};
    glm::dvec3 all(0.0);
    double allWeight = 0.0;
    for (std::uint32_t t : tris) {
        const glm::dvec3 c = glm::cross(corner(m, t, 1) - corner(m, t, 0), corner(m, t, 2) - corner(m, t, 0));
        const double area = 0.5 * glm::length(c);
        if (area <= 0.0) continue;
        const glm::dvec3 n = c / (2.0 * area);
        const glm::dvec3 colour(materialMeanColour(materialOf(m, t)));
        for (int f = 0; f < 6; ++f) {
            const double wgt = area * std::max(0.0, glm::dot(n, faces[f]));
            sum[f] += wgt * colour;
            weight[f] += wgt;
        }
        all += area * colour;
        allWeight += area;
    }
    const glm::dvec3 fallback = allWeight > 0.0 ? all / allWeight : glm::dvec3(materialMeanColour(kConcrete));
    for (int f = 0; f < 6; ++f) box.colours[std::size_t(f)] = glm::vec3(weight[f] > 1e-9 ? sum[f] / weight[f] : fallback);
}

ProxyBox makeBox(const std::string& name, int part, const char* kind, const PlanBox& plan, double y0, double y1) {
    ProxyBox b;
    b.name = name;
    b.part = part;
    b.kind = kind;
    b.u = {plan.u.x, 0.0, plan.u.y};
    b.w = {plan.w.x, 0.0, plan.w.y};
    const glm::dvec2 mid = 0.5 * (plan.lo + plan.hi);
    const glm::dvec2 centre = mid.x * plan.u + mid.y * plan.w;
    b.centre = {centre.x, 0.5 * (y0 + y1), centre.y};
    // Flat ground is a slab 10 cm thick (centred on it), so that every box has a volume.
    constexpr double kMinHalf = 0.05;
    b.halfSize = glm::max(glm::dvec3(0.5 * (plan.hi.x - plan.lo.x), 0.5 * (y1 - y0), 0.5 * (plan.hi.y - plan.lo.y)), glm::dvec3(kMinHalf));
    return b;
}

// Boxes for the triangles `tris`: one fitted box, or two when one is too empty.
void boxesOf(const std::string& name, const char* kind, const Mesh& m, const std::vector<std::uint32_t>& tris, int& part,
             std::vector<ProxyBox>& out, bool allowCut) {
    std::vector<glm::dvec2> pts;
    for (std::uint32_t t : tris)
        for (int k = 0; k < 3; ++k) pts.emplace_back(corner(m, t, k).x, corner(m, t, k).z);
    const std::vector<glm::dvec2> hull = convexHull(pts);
    const PlanBox box = fitPlan(hull);
    const double rectArea = (box.hi.x - box.lo.x) * (box.hi.y - box.lo.y);
    std::vector<std::pair<PlanBox, std::vector<std::uint32_t>>> pieces;
    if (allowCut && hull.size() >= 3 && rectArea > 0.0 && polygonArea(hull) / rectArea < kMinFill) {
        // Cut across the long side, at its middle; each half gets its own fitted box.
        const bool alongU = box.hi.x - box.lo.x >= box.hi.y - box.lo.y;
        const glm::dvec2 axis = alongU ? box.u : box.w;
        const double cut = alongU ? 0.5 * (box.lo.x + box.hi.x) : 0.5 * (box.lo.y + box.hi.y);
        for (double side : {-1.0, 1.0}) {
            std::vector<std::uint32_t> mine;
            for (std::uint32_t t : tris) {
                const glm::dvec3 c = (corner(m, t, 0) + corner(m, t, 1) + corner(m, t, 2)) / 3.0;
                const double d = glm::dot(glm::dvec2(c.x, c.z), axis) - cut;
                if ((side < 0.0) == (d < 0.0)) mine.push_back(t);
            }
            const std::vector<glm::dvec2> half = clip(hull, axis, cut, side);
            if (mine.empty() || half.size() < 3) continue;
            pieces.emplace_back(fitPlan(convexHull(half)), std::move(mine));
        }
    }
    if (pieces.empty()) pieces.emplace_back(box, tris);
    for (auto& [plan, mine] : pieces) {
        double y0 = INFINITY, y1 = -INFINITY;
        for (std::uint32_t t : mine)
            for (int k = 0; k < 3; ++k) y0 = std::min(y0, corner(m, t, k).y), y1 = std::max(y1, corner(m, t, k).y);
        ProxyBox b = makeBox(name, part++, kind, plan, y0, y1);
        colourFaces(b, m, mine);
        out.push_back(std::move(b));
    }
}

// A flat terrain (within 0.5 m) stays one box; hills and the sloping sea floor are cut into
// kTerrainChunk-metre squares (by triangle centroid), each its own box, so that no box reaches
// from a valley floor to a hilltop over the whole tile.
constexpr double kTerrainChunk = 20.0;  // two 10 m ground cells: up to 6 m of hill slope
std::vector<std::vector<std::uint32_t>> terrainChunks(const Mesh& m, const std::vector<std::uint32_t>& tris) {
    double y0 = INFINITY, y1 = -INFINITY;
    for (std::uint32_t t : tris)
        for (int k = 0; k < 3; ++k) y0 = std::min(y0, corner(m, t, k).y), y1 = std::max(y1, corner(m, t, k).y);
    if (y1 - y0 <= 0.5) return {tris};
    std::map<std::pair<long, long>, std::vector<std::uint32_t>> chunks;  // ordered: the same boxes every run
    for (std::uint32_t t : tris) {
        const glm::dvec3 c = (corner(m, t, 0) + corner(m, t, 1) + corner(m, t, 2)) / 3.0;
        chunks[{long(std::floor(c.x / kTerrainChunk)), long(std::floor(c.z / kTerrainChunk))}].push_back(t);
    }
    std::vector<std::vector<std::uint32_t>> out;
    for (auto& [key, chunk] : chunks) out.push_back(std::move(chunk));
    return out;
}

}  // namespace

std::vector<ProxyBox> buildingProxies(const std::string& name, const Mesh& lod1) {
    std::vector<ProxyBox> out;
    int part = 0;
    for (const std::vector<std::uint32_t>& tris : parts(lod1)) boxesOf(name, "building", lod1, tris, part, out, true);
    return out;
}

std::vector<ProxyBox> groundProxies(const std::string& name, const Mesh& ground) {
    std::vector<ProxyBox> out;
    std::vector<std::vector<std::uint32_t>> all = parts(ground);
    if (all.empty()) return out;
    // The terrain is the largest part; every other part is a kerb.
    std::size_t terrain = 0;
    for (std::size_t i = 1; i < all.size(); ++i)
        if (all[i].size() > all[terrain].size()) terrain = i;
    int part = 0;
    std::map<std::uint8_t, std::vector<std::uint32_t>> byMaterial;  // land and shore apart
    for (std::uint32_t t : all[terrain]) byMaterial[materialOf(ground, t)].push_back(t);
    for (const auto& [material, tris] : byMaterial)
        for (const std::vector<std::uint32_t>& chunk : terrainChunks(ground, tris))
            boxesOf(name, "ground", ground, chunk, part, out, false);
    for (std::size_t i = 0; i < all.size(); ++i)
        if (i != terrain) boxesOf(name, "kerb", ground, all[i], part, out, false);
    return out;
}

std::vector<ProxyBox> streetProxies(const std::string& cityJson, const std::string& source) {
    std::vector<ProxyBox> out;
    try {
        const nlohmann::json j = nlohmann::json::parse(cityJson);
        if (!j.contains("streets")) return out;
        // A world's tile (city.json "origin") is in its own frame: plan (x, y) -> (x - ox, oy - y).
        const auto o = j.contains("origin") ? j["origin"].get<std::array<double, 2>>() : std::array<double, 2>{0.0, 0.0};
        const glm::dvec2 origin(o[0], -o[1]);
        for (const nlohmann::json& s : j["streets"]) {
            const std::string name = format("street_{}", s.at("id").get<int>());
            const double width = s.at("width").get<double>();
            const auto& line = s.at("polyline");
            for (std::size_t i = 0; i + 1 < line.size(); ++i) {
                // plan (x, y) -> glTF (x, z = -y)
                const glm::dvec2 a = glm::dvec2(line[i][0].get<double>(), -line[i][1].get<double>()) - origin;
                const glm::dvec2 b = glm::dvec2(line[i + 1][0].get<double>(), -line[i + 1][1].get<double>()) - origin;
                const double length = glm::distance(a, b);
                if (length <= 1e-9) continue;
                PlanBox plan;
                plan.u = (b - a) / length;
                plan.w = {-plan.u.y, plan.u.x};
                const glm::dvec2 ua(glm::dot(a, plan.u), glm::dot(a, plan.w));
                plan.lo = ua - glm::dvec2(0.0, 0.5 * width);
                plan.hi = ua + glm::dvec2(length, 0.5 * width);
                ProxyBox box = makeBox(name, int(i), "street", plan, -0.1, 0.0);
                box.colours.fill(materialMeanColour(kAsphalt));
                out.push_back(std::move(box));
            }
        }
    } catch (const nlohmann::json::exception& e) {
        throw InputError(format("{}: streets: {}", source, oneLine(e.what())));
    }
    return out;
}

void applyProxyOverrides(std::vector<ProxyBox>& boxes, const std::string& json, const std::string& source) {
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(json);
    } catch (const nlohmann::json::exception& e) {
        throw InputError(format("{}: {}", source, oneLine(e.what())));
    }
    if (!j.is_object() || j.value("format", "") != "dawnforge.proxy_colours" || j.value("version", 0) != 1)
        throw InputError(format("{}: expected {{\"format\": \"dawnforge.proxy_colours\", \"version\": 1, \"boxes\": {{...}}}}", source));
    for (const auto& [key, value] : j.items())
        if (key != "format" && key != "version" && key != "boxes")
            throw InputError(format("{}: unknown key \"{}\" (allowed: format, version, boxes)", source, key));
    if (!j.contains("boxes")) return;
    if (!j["boxes"].is_object()) throw InputError(format("{}: \"boxes\" must be an object", source));
    for (const auto& [key, faces] : j["boxes"].items()) {
        std::string name = key;
        int part = -1;
        if (const auto slash = key.rfind('/'); slash != std::string::npos) {
            name = key.substr(0, slash);
            const std::string digits = key.substr(slash + 1);
            if (digits.empty() || digits.size() > 6 || !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }))
                throw InputError(format("{}: boxes.\"{}\": expected NAME or NAME/PART", source, key));
            part = std::stoi(digits);
        }
        std::vector<ProxyBox*> targets;
        for (ProxyBox& b : boxes)
            if (b.name == name && (part < 0 || b.part == part)) targets.push_back(&b);
        if (targets.empty()) throw InputError(format("{}: boxes.\"{}\": no such box in this city", source, key));
        if (!faces.is_object()) throw InputError(format("{}: boxes.\"{}\" must be an object of faces", source, key));
        for (const auto& [face, colour] : faces.items()) {
            const auto it = std::find_if(kProxyFaces.begin(), kProxyFaces.end(), [&](const char* f) { return face == f; });
            if (it == kProxyFaces.end())
                throw InputError(format("{}: boxes.\"{}\": unknown face \"{}\" (allowed: +u, -u, +y, -y, +w, -w)", source, key, face));
            if (!colour.is_array() || colour.size() != 3 || !std::all_of(colour.begin(), colour.end(), [](const nlohmann::json& c) {
                    return c.is_number() && c.get<double>() >= 0.0 && c.get<double>() <= 1.0;
                }))
                throw InputError(format("{}: boxes.\"{}\".\"{}\": expected [r, g, b], each 0 to 1", source, key, face));
            const std::size_t f = std::size_t(it - kProxyFaces.begin());
            for (ProxyBox* b : targets) {
                b->colours[f] = glm::vec3(colour[0].get<float>(), colour[1].get<float>(), colour[2].get<float>());
                if (std::find(b->overridden.begin(), b->overridden.end(), face) == b->overridden.end()) b->overridden.push_back(face);
            }
        }
    }
}

std::string proxiesJson(const std::vector<ProxyBox>& boxes) {
    const auto r = [](double v) { return std::round(v * 1000.0) / 1000.0; };
    const auto v3 = [&](glm::dvec3 v) { return nlohmann::ordered_json::array({r(v.x), r(v.y), r(v.z)}); };
    nlohmann::ordered_json j;
    j["format"] = "dawnforge.proxies";
    j["version"] = 1;
    j["faces"] = kProxyFaces;
    nlohmann::ordered_json list = nlohmann::ordered_json::array();
    for (const ProxyBox& b : boxes) {
        nlohmann::ordered_json colours = nlohmann::ordered_json::array();
        for (const glm::vec3& c : b.colours) colours.push_back(v3(glm::dvec3(c)));
        nlohmann::ordered_json e{{"name", b.name}, {"part", b.part}, {"kind", b.kind}, {"centre", v3(b.centre)},
                                 {"u", v3(b.u)},   {"w", v3(b.w)},     {"half_size", v3(b.halfSize)}, {"colours", std::move(colours)}};
        if (!b.overridden.empty()) e["overridden"] = b.overridden;
        list.push_back(std::move(e));
    }
    j["boxes"] = std::move(list);
    return j.dump(1) + "\n";
}

}  // namespace dawnforge::bake
