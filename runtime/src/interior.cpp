// Perspective interior mapping: the CPU reference of runtime/shaders/interior.glsl and the
// generator of its room pictures and middle-layer cut-outs. Technique: "Perspective Interior
// Mapping" / "Extended Perspective Interior Mapping" (Undawn, GDC 2024).
#include <dawnforge/core/error.hpp>
#include <dawnforge/core/seed.hpp>
#include <dawnforge/runtime/interior.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

namespace dawnforge::runtime {
namespace {

// Hash of a few integers to [0, 1).
double hash01(std::uint32_t a, std::uint32_t b = 0, std::uint32_t c = 0, std::uint32_t d = 0) {
    std::uint32_t h = lowbias32(d + 0x27d4eb2fu);
    h = lowbias32((c + 0x85ebca6bu) ^ h);
    h = lowbias32((b + 0x9e3779b9u) ^ h);
    h = lowbias32(a ^ h);
    return static_cast<double>(h >> 8) * (1.0 / 16777216.0);
}
std::uint32_t cell(double v) { return static_cast<std::uint32_t>(static_cast<std::int32_t>(std::floor(v))); }

using glm::dvec2;
using glm::dvec3;

double smooth(double e0, double e1, double x) {
    const double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}
bool inRect(dvec2 p, dvec2 lo, dvec2 hi) { return p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y; }
// Rounded rectangle test.
bool inRoundRect(dvec2 p, dvec2 lo, dvec2 hi, double r) {
    const dvec2 c = 0.5 * (lo + hi), h = 0.5 * (hi - lo) - r;
    const dvec2 q = glm::max(glm::abs(p - c) - h, dvec2(0.0));
    return glm::length(q) <= r && std::abs(p.x - c.x) <= 0.5 * (hi.x - lo.x) && std::abs(p.y - c.y) <= 0.5 * (hi.y - lo.y);
}
bool inEllipse(dvec2 p, dvec2 c, dvec2 r) {
    const dvec2 q = (p - c) / r;
    return glm::dot(q, q) <= 1.0;
}
bool inCapsule(dvec2 p, dvec2 a, dvec2 b, double r) {
    const dvec2 pa = p - a, ba = b - a;
    const double h = std::clamp(glm::dot(pa, ba) / glm::dot(ba, ba), 0.0, 1.0);
    return glm::length(pa - ba * h) <= r;
}

dvec3 srgbToLinear(dvec3 c) {
    dvec3 out;
    for (int i = 0; i < 3; ++i) out[i] = c[i] <= 0.04045 ? c[i] / 12.92 : std::pow((c[i] + 0.055) / 1.055, 2.4);
    return out;
}
std::uint8_t linearToSrgb8(double c) {
    c = std::clamp(c, 0.0, 1.0);
    const double s = c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
    return static_cast<std::uint8_t>(std::lround(s * 255.0));
}
dvec3 rgb(int r, int g, int b) { return srgbToLinear(dvec3(r, g, b) / 255.0); }

// The room the pictures show, in metres; real rooms stretch it to their own size.
constexpr dvec3 kRoomMetres{4.0, 2.8, 5.0};

enum class WallPattern { Plain, Stripes, Dots };
enum class FloorKind { Planks, Tiles, Carpet };
enum class Feature { None, Window, Picture, Door };

struct RoomStyle {
    dvec3 wall, wallAccent, skirting, door, floorA, floorB, ceiling, pictureColours[3];
    WallPattern pattern;
    FloorKind floor;
    Feature back, left, right;
    std::uint32_t seed;
};

RoomStyle makeStyle(int s) {
    static const std::array<dvec3, 8> walls{rgb(236, 226, 200), rgb(190, 210, 222), rgb(196, 210, 180), rgb(232, 200, 196),
                                            rgb(205, 205, 208), rgb(226, 212, 170), rgb(245, 242, 234), rgb(176, 186, 204)};
    static const std::array<dvec3, 4> woods{rgb(150, 104, 64), rgb(186, 142, 96), rgb(112, 74, 48), rgb(204, 170, 120)};
    static const std::array<dvec3, 4> carpets{rgb(120, 56, 52), rgb(70, 84, 110), rgb(150, 140, 120), rgb(86, 104, 80)};
    const std::uint32_t seed = lowbias32(static_cast<std::uint32_t>(s) * 0x9e3779b9u + 0x51ed270bu);
    auto pick = [&](std::uint32_t purpose, int n) { return static_cast<int>(hash01(seed, purpose) * n); };
    RoomStyle st{};
    st.seed = seed;
    st.wall = walls[static_cast<std::size_t>(s) % walls.size()] * (0.92 + 0.12 * hash01(seed, 1));
    st.wallAccent = st.wall * 0.82;
    st.pattern = static_cast<WallPattern>((s / 2 + pick(2, 2)) % 3);
    st.floor = static_cast<FloorKind>(s % 3);
    switch (st.floor) {
    case FloorKind::Planks:
        st.floorA = woods[static_cast<std::size_t>(pick(3, 4))];
        st.floorB = st.floorA * 0.8;
        break;
    case FloorKind::Tiles:
        st.floorA = pick(3, 2) == 0 ? rgb(214, 210, 200) : rgb(170, 176, 180);
        st.floorB = pick(4, 2) == 0 ? st.floorA * 0.55 : rgb(90, 92, 96);
        break;
    case FloorKind::Carpet:
        st.floorA = carpets[static_cast<std::size_t>(pick(3, 4))];
        st.floorB = st.floorA * 0.9;
        break;
    }
    st.skirting = pick(5, 2) == 0 ? rgb(240, 238, 232) : woods[static_cast<std::size_t>(pick(6, 4))] * 0.8;
    st.ceiling = rgb(240, 238, 232);
    st.door = pick(9, 3) == 0 ? rgb(226, 222, 212) : woods[static_cast<std::size_t>(pick(10, 4))] * 0.9;
    for (int i = 0; i < 3; ++i)
        st.pictureColours[i] = srgbToLinear(dvec3(hash01(seed, 10 + i, 0), hash01(seed, 10 + i, 1), hash01(seed, 10 + i, 2)) * 0.8 + 0.1);
    static const std::array<Feature, 4> backs{Feature::Window, Feature::Picture, Feature::None, Feature::Window};
    st.back = backs[static_cast<std::size_t>(s) % backs.size()];
    const bool doorLeft = pick(7, 2) == 0;
    st.left = doorLeft ? Feature::Door : (pick(8, 2) == 0 ? Feature::Picture : Feature::None);
    st.right = doorLeft ? (pick(8, 2) == 0 ? Feature::Picture : Feature::None) : Feature::Door;
    return st;
}

// Emissive or lit surface colour.
struct Surface {
    dvec3 albedo;
    bool emissive = false;
};

Surface wallSurface(const RoomStyle& st, Feature feature, double a, double b, double wallLength, std::uint32_t wallId) {
    // a: metres along the wall, b: metres up.
    switch (feature) {
    case Feature::Window: {
        const dvec2 lo(0.5 * wallLength - 0.8, 0.9), hi(0.5 * wallLength + 0.8, 2.3);
        if (inRect({a, b}, lo - 0.07, hi + 0.07)) {
            if (!inRect({a, b}, lo, hi) || std::abs(a - 0.5 * wallLength) < 0.03 || std::abs(b - 1.75) < 0.03)
                return {rgb(236, 236, 232)};
            const double t = (b - lo.y) / (hi.y - lo.y);
            return {glm::mix(rgb(150, 168, 186), rgb(96, 128, 170), t) * 0.9, true};
        }
        if (inRect({a, b}, {lo.x - 0.12, lo.y - 0.1}, {hi.x + 0.12, lo.y - 0.04})) return {rgb(236, 236, 232)};  // sill
        break;
    }
    case Feature::Picture: {
        const double c = wallId == 0 ? 0.5 * wallLength : 0.55 * wallLength;
        const dvec2 lo(c - 0.5, 1.2), hi(c + 0.5, 1.9);
        if (inRect({a, b}, lo - 0.05, hi + 0.05)) {
            if (!inRect({a, b}, lo, hi)) return {rgb(60, 44, 32)};
            const double u = (a - lo.x) / (hi.x - lo.x), v = (b - lo.y) / (hi.y - lo.y);
            const int k = u + 0.3 * v < 0.45 ? 0 : (v > 0.55 ? 1 : 2);
            return {st.pictureColours[k]};
        }
        break;
    }
    case Feature::Door: {
        const double c = 0.72 * wallLength;
        const dvec2 lo(c - 0.45, 0.0), hi(c + 0.45, 2.05);
        if (inRect({a, b}, {lo.x - 0.06, 0.0}, hi + 0.06)) {
            if (!inRect({a, b}, lo, hi)) return {rgb(236, 234, 228)};
            if (glm::length(dvec2(a - (wallId == 1 ? hi.x - 0.1 : lo.x + 0.1), b - 1.02)) < 0.035) return {rgb(200, 190, 150)};
            const bool panel = inRect({a, b}, lo + dvec2(0.12, 0.15), {hi.x - 0.12, 0.95}) ||
                               inRect({a, b}, {lo.x + 0.12, 1.1}, hi - dvec2(0.12, 0.15));
            return {st.door * (panel ? 0.85 : 1.0)};
        }
        break;
    }
    case Feature::None: break;
    }
    if (b < 0.09) return {st.skirting};
    dvec3 c = st.wall;
    switch (st.pattern) {
    case WallPattern::Plain: break;
    case WallPattern::Stripes:
        if (std::fmod(a + 10.0, 0.3) < 0.15) c = st.wallAccent;
        break;
    case WallPattern::Dots: {
        const dvec2 q(std::fmod(a + 10.0, 0.25) - 0.125, std::fmod(b + 10.0 + (std::fmod(a + 10.0, 0.5) < 0.25 ? 0.125 : 0.0), 0.25) - 0.125);
        if (glm::length(q) < 0.035) c = st.wallAccent;
        break;
    }
    }
    return {c};
}

Surface floorSurface(const RoomStyle& st, double xm, double zm) {
    switch (st.floor) {
    case FloorKind::Planks: {
        const double w = 0.2, len = 1.4;
        const double row = std::floor(xm / w);
        const double zz = zm + hash01(st.seed, 20, cell(row)) * len;
        const double col = std::floor(zz / len);
        const double fx = xm - row * w, fz = zz - col * len;
        if (fx < 0.008 || fz < 0.012) return {st.floorB * 0.6};
        const double grain = 0.06 * std::sin(fx * 90.0 + 3.0 * std::sin(zz * 7.0 + row));
        return {glm::mix(st.floorA, st.floorB, hash01(st.seed, 21, cell(row), cell(col))) * (1.0 + grain)};
    }
    case FloorKind::Tiles: {
        const double t = 0.5;
        const double fx = std::fmod(xm + 10.0, t), fz = std::fmod(zm + 10.0, t);
        if (fx < 0.012 || fz < 0.012) return {st.floorB * 0.7};
        const bool odd = (cell(xm / t) + cell(zm / t)) % 2u == 1u;
        return {(odd ? st.floorB : st.floorA) * (0.97 + 0.06 * hash01(st.seed, 22, cell(xm / t), cell(zm / t)))};
    }
    case FloorKind::Carpet: {
        const double n = hash01(st.seed, 23, cell(xm * 60.0), cell(zm * 60.0));
        return {st.floorA * (0.94 + 0.1 * n)};
    }
    }
    return {st.floorA};
}

constexpr dvec3 kLamp{0.5 * kRoomMetres.x, kRoomMetres.y - 0.3, 0.5 * kRoomMetres.z};

// Linear radiance of one room point.
dvec3 shadeRoom(const RoomStyle& st, const RoomHit& hit) {
    const dvec3 p = hit.point;
    const dvec3 m = p * kRoomMetres;
    dvec3 normal(0.0, 0.0, -1.0);
    Surface surf;
    switch (hit.face) {
    case RoomFace::Back: normal = {0, 0, -1}; surf = wallSurface(st, st.back, m.x, m.y, kRoomMetres.x, 0); break;
    case RoomFace::Left: normal = {1, 0, 0}; surf = wallSurface(st, st.left, m.z, m.y, kRoomMetres.z, 1); break;
    case RoomFace::Right: normal = {-1, 0, 0}; surf = wallSurface(st, st.right, m.z, m.y, kRoomMetres.z, 2); break;
    case RoomFace::Floor: normal = {0, 1, 0}; surf = floorSurface(st, m.x, m.z); break;
    case RoomFace::Ceiling: {
        normal = {0, -1, 0};
        const double r = glm::length(dvec2(m.x - kLamp.x, m.z - kLamp.z));
        if (r < 0.22) return rgb(255, 244, 214) * 1.1;
        surf = {st.ceiling * (1.0 + 1.4 * std::exp(-r * r / 0.8))};
        if (r < 0.27) surf.albedo = rgb(90, 84, 76);
        break;
    }
    }
    if (surf.emissive) return surf.albedo;
    const dvec3 toLamp = kLamp - m;
    const double d2 = glm::dot(toLamp, toLamp);
    const double direct = std::max(glm::dot(normal, toLamp / std::sqrt(d2)), 0.0) * 2.6 / (1.0 + 0.22 * d2);
    // Ambient occlusion towards the room's edges (not the glass's: light comes in there).
    double ao = 1.0;
    const std::array<double, 5> edgeDistances{m.x, kRoomMetres.x - m.x, m.y, kRoomMetres.y - m.y, kRoomMetres.z - m.z};
    const std::array<int, 5> axisOf{0, 0, 1, 1, 2};
    const int faceAxis = hit.face == RoomFace::Back ? 2 : (hit.face == RoomFace::Left || hit.face == RoomFace::Right ? 0 : 1);
    for (std::size_t i = 0; i < edgeDistances.size(); ++i)
        if (axisOf[i] != faceAxis) ao *= 1.0 - 0.45 * std::exp(-edgeDistances[i] / 0.25);
    return surf.albedo * (0.32 + direct) * ao * 0.85;
}

// One middle-layer cut-out sample: colour (linear) and coverage.
struct Cutout {
    dvec3 colour{0.0};
    bool covered = false;
};

Cutout sofaAt(dvec2 p, double x0, double x1, dvec3 colour) {
    const double shade = 0.75 + 0.25 * smooth(0.1, 0.9, p.y);
    if (inRoundRect(p, {x0, 0.42}, {x1, 0.95}, 0.1)) return {colour * 0.85 * shade, true};                 // backrest
    if (inRoundRect(p, {x0 - 0.08, 0.12}, {x0 + 0.16, 0.66}, 0.07)) return {colour * 0.95 * shade, true};  // arms
    if (inRoundRect(p, {x1 - 0.16, 0.12}, {x1 + 0.08, 0.66}, 0.07)) return {colour * 0.95 * shade, true};
    if (inRoundRect(p, {x0, 0.12}, {x1, 0.46}, 0.05)) return {colour * (std::fmod(p.x - x0, (x1 - x0) / 3.0) < 0.015 ? 0.7 : 1.0), true};
    if (p.y < 0.12 && p.y >= 0.0 && (std::abs(p.x - x0) < 0.04 || std::abs(p.x - x1) < 0.04)) return {rgb(40, 30, 24), true};
    return {};
}
Cutout shelfAt(dvec2 p, double x0, double x1, std::uint32_t seed) {
    if (!inRect(p, {x0, 0.0}, {x1, 2.0})) return {};
    const dvec3 wood = rgb(120, 84, 56);
    if (p.x < x0 + 0.04 || p.x > x1 - 0.04 || p.y > 1.96 || std::fmod(p.y, 0.45) < 0.035) return {wood * (p.y < 0.035 ? 0.7 : 1.0), true};
    const double shelfY = std::fmod(p.y, 0.45);
    const std::uint32_t row = cell(p.y / 0.45);
    // Books of varying width and height along each shelf.
    double bx = x0 + 0.04;
    for (std::uint32_t i = 0; bx < x1 - 0.04; ++i) {
        const double w = 0.035 + 0.05 * hash01(seed, 30, row * 64 + i);
        const double h = 0.22 + 0.14 * hash01(seed, 31, row * 64 + i);
        const bool gap = hash01(seed, 32, row * 64 + i) < 0.12;
        if (p.x < bx + w) {
            if (gap || shelfY > h + 0.035 || bx + w > x1 - 0.04) break;
            const dvec3 c(hash01(seed, 33, row * 64 + i), hash01(seed, 34, row * 64 + i), hash01(seed, 35, row * 64 + i));
            return {srgbToLinear(0.2 + 0.6 * c) * (p.x > bx + w - 0.006 ? 0.6 : 1.0), true};
        }
        bx += w;
    }
    return {wood * 0.45, true};  // the shelf's back panel, in shadow
}
Cutout plantAt(dvec2 p, double cx, std::uint32_t seed) {
    if (p.y >= 0.0 && p.y <= 0.42 && std::abs(p.x - cx) < 0.14 + 0.06 * p.y / 0.42)  // the pot, wider at the top
        return {rgb(168, 92, 60) * (p.y > 0.36 ? 0.8 : 1.0), true};
    for (std::uint32_t i = 0; i < 14; ++i) {
        const double a = -1.2 + 2.4 * hash01(seed, 40, i);
        const double len = 0.45 + 0.55 * hash01(seed, 41, i);
        const dvec2 base(cx, 0.42), dir(std::sin(a), std::cos(a));
        const dvec2 c = base + dir * len * 0.55;
        const dvec2 q = p - c;
        const dvec2 local(glm::dot(q, dvec2(dir.y, -dir.x)), glm::dot(q, dir));
        if (inEllipse(local, {0, 0}, {0.09, len * 0.5}))
            return {rgb(54, 110, 48) * (0.7 + 0.5 * hash01(seed, 42, i)) * (local.x > 0 ? 0.8 : 1.0), true};
    }
    return {};
}
Cutout personAt(dvec2 p, double cx, std::uint32_t seed) {
    const dvec3 shirt = srgbToLinear(dvec3(hash01(seed, 50), hash01(seed, 51), hash01(seed, 52)) * 0.5 + 0.15);
    const dvec3 trousers = rgb(40, 44, 56), skin = rgb(150, 110, 90), hair = rgb(40, 30, 26);
    if (inEllipse(p, {cx, 1.62}, {0.1, 0.125})) return {p.y > 1.66 ? hair : skin, true};
    if (inRect(p, {cx - 0.045, 1.42}, {cx + 0.045, 1.52})) return {skin * 0.85, true};  // neck
    if (inRoundRect(p, {cx - 0.21, 0.88}, {cx + 0.21, 1.48}, 0.08)) return {shirt * (p.x > cx + 0.1 ? 0.8 : 1.0), true};
    if (inCapsule(p, {cx - 0.22, 1.38}, {cx - 0.27, 0.9}, 0.055) || inCapsule(p, {cx + 0.22, 1.38}, {cx + 0.27, 0.9}, 0.055))
        return {shirt * 0.85, true};
    if (inCapsule(p, {cx - 0.27, 0.9}, {cx - 0.27, 0.86}, 0.05) || inCapsule(p, {cx + 0.27, 0.9}, {cx + 0.27, 0.86}, 0.05))
        return {skin, true};
    if (inCapsule(p, {cx - 0.1, 0.9}, {cx - 0.11, 0.08}, 0.075) || inCapsule(p, {cx + 0.1, 0.9}, {cx + 0.11, 0.08}, 0.075))
        return {trousers, true};
    if (inRoundRect(p, {cx - 0.2, 0.0}, {cx + 0.2, 0.07}, 0.03) && std::abs(p.x - cx) > 0.02) return {rgb(24, 20, 18), true};
    return {};
}

// The middle layer of one style at room point (x, y) in metres.
Cutout middleAt(int s, const RoomStyle& st, dvec2 p) {
    // Pairs of items, left and right, chosen per style; every style shows something.
    const int layout = s % 6;
    const dvec3 sofaColour = srgbToLinear(dvec3(hash01(st.seed, 60), hash01(st.seed, 61), hash01(st.seed, 62)) * 0.45 + 0.2);
    const auto person = [&](double cx) { return personAt(p, cx, st.seed); };
    const auto plant = [&](double cx) { return plantAt(p, cx, st.seed); };
    Cutout c;
    switch (layout) {
    case 0: c = sofaAt(p, 0.35, 2.15, sofaColour); if (!c.covered) c = plant(3.4); break;
    case 1: c = person(1.0); if (!c.covered) c = shelfAt(p, 2.9, 3.85, st.seed); break;
    case 2: c = plant(0.5); if (!c.covered) c = person(2.9); break;
    case 3: c = shelfAt(p, 0.1, 1.0, st.seed); if (!c.covered) c = sofaAt(p, 1.9, 3.6, sofaColour); break;
    case 4: c = person(2.8); if (!c.covered) c = sofaAt(p, 0.3, 1.9, sofaColour); break;
    default: c = plant(3.5); if (!c.covered) c = shelfAt(p, 0.15, 1.05, st.seed); break;
    }
    return c;
}

}  // namespace

dvec3 roomRay(dvec3 viewDir, dvec3 normal, dvec3 roomSize) {
    const dvec3 inward = -normal;
    const dvec3 right = glm::normalize(glm::cross(inward, dvec3(0.0, 1.0, 0.0)));
    const dvec3 up = glm::cross(right, inward);
    return {glm::dot(viewDir, right) / roomSize.x, glm::dot(viewDir, up) / roomSize.y, glm::dot(viewDir, inward) / roomSize.z};
}

RoomHit roomExit(dvec3 origin, dvec3 direction) {
    DAWNFORGE_ASSERT(direction.z > 0.0, "the direction must point into the room (z > 0)");
    constexpr double kSlack = 1e-12;
    DAWNFORGE_ASSERT(origin.x >= -kSlack && origin.x <= 1.0 + kSlack && origin.y >= -kSlack && origin.y <= 1.0 + kSlack &&
                origin.z >= -kSlack && origin.z < 1.0, "the origin must lie in the room box [0,1]^3, short of the back wall");
    double best = std::numeric_limits<double>::infinity();
    int axis = 2;
    for (int i = 0; i < 3; ++i) {
        if (direction[i] == 0.0) continue;
        const double distance = direction[i] > 0.0 ? 1.0 - origin[i] : origin[i];
        const double t = distance / std::abs(direction[i]);
        if (t < best) {
            best = t;
            axis = i;
        }
    }
    dvec3 point = glm::clamp(origin + best * direction, dvec3(0.0), dvec3(1.0));
    point[axis] = direction[axis] > 0.0 ? 1.0 : 0.0;
    static constexpr RoomFace kFaces[3][2] = {{RoomFace::Left, RoomFace::Right}, {RoomFace::Floor, RoomFace::Ceiling}, {RoomFace::Back, RoomFace::Back}};
    return {kFaces[axis][direction[axis] > 0.0 ? 1 : 0], point, best};
}

glm::dvec2 roomTextureUv(dvec3 roomPoint, double backShare) {
    DAWNFORGE_ASSERT(backShare > 0.0 && backShare < 1.0, "the back wall's share must lie in (0, 1)");
    const double s = 1.0 / (1.0 + roomPoint.z * (1.0 / backShare - 1.0));
    return 0.5 + (dvec2(roomPoint) - 0.5) * s;
}

RoomHit roomPointAtUv(dvec2 uv, double backShare) {
    DAWNFORGE_ASSERT(backShare > 0.0 && backShare < 1.0, "the back wall's share must lie in (0, 1)");
    const dvec2 q = glm::clamp(uv, dvec2(0.0), dvec2(1.0)) - 0.5;
    // s(z) is the picture's scale at depth z: the point's square ring in the picture has half-side s/2.
    const double s = 2.0 * std::max(std::abs(q.x), std::abs(q.y));
    if (s <= backShare) return {RoomFace::Back, dvec3(0.5 + q / backShare, 1.0), 1.0 / backShare};
    const double z = std::clamp((1.0 / s - 1.0) / (1.0 / backShare - 1.0), 0.0, 1.0);
    dvec3 p(0.5 + q / s, z);
    RoomFace face;
    if (std::abs(q.x) >= std::abs(q.y)) {
        face = q.x < 0.0 ? RoomFace::Left : RoomFace::Right;
        p.x = q.x < 0.0 ? 0.0 : 1.0;
    } else {
        face = q.y < 0.0 ? RoomFace::Floor : RoomFace::Ceiling;
        p.y = q.y < 0.0 ? 0.0 : 1.0;
    }
    p = glm::clamp(p, dvec3(0.0), dvec3(1.0));
    return {face, p, 1.0 / s};
}

std::optional<dvec3> middleLayerHit(dvec3 origin, dvec3 direction, double depth) {
    if (direction.z == 0.0) return std::nullopt;
    const double t = (depth - origin.z) / direction.z;
    if (!(t > 0.0)) return std::nullopt;
    dvec3 hit = origin + t * direction;
    hit.z = depth;
    if (hit.x < 0.0 || hit.x > 1.0 || hit.y < 0.0 || hit.y > 1.0 || depth < 0.0 || depth > 1.0) return std::nullopt;
    return hit;
}

int roomStyle(std::uint32_t building, std::uint32_t room, int styles) {
    DAWNFORGE_ASSERT(styles > 0, "there must be at least one style");
    const std::uint32_t h = lowbias32(building ^ lowbias32(room + 0x9e3779b9u));
    return static_cast<int>(h % static_cast<std::uint32_t>(styles));
}

InteriorTextures generateInteriors(int roomSize, int styles) {
    DAWNFORGE_ASSERT(roomSize >= 16 && (roomSize & (roomSize - 1)) == 0, "roomSize must be a power of two >= 16");
    DAWNFORGE_ASSERT(styles >= 1, "there must be at least one style");
    InteriorTextures out;
    out.roomSize = roomSize;
    out.styles = styles;
    const std::size_t width = static_cast<std::size_t>(roomSize) * static_cast<std::size_t>(styles);
    const std::size_t texels = width * static_cast<std::size_t>(roomSize);
    out.rooms.assign(texels * 4, 0);
    out.middle.assign(texels * 4, 0);
    static constexpr double kSub[2] = {0.25, 0.75};
    std::vector<dvec3> midColour(static_cast<std::size_t>(roomSize) * roomSize);
    std::vector<int> midCoverage(midColour.size());
    std::vector<bool> known(midColour.size());

    for (int s = 0; s < styles; ++s) {
        const RoomStyle st = makeStyle(s);
        for (int j = 0; j < roomSize; ++j) {
            for (int i = 0; i < roomSize; ++i) {
                dvec3 room(0.0), mid(0.0);
                int covered = 0;
                for (double sy : kSub) {
                    for (double sx : kSub) {
                        const dvec2 uv((i + sx) / roomSize, (j + sy) / roomSize);
                        room += shadeRoom(st, roomPointAtUv(uv));
                        const Cutout c = middleAt(s, st, uv * dvec2(kRoomMetres));
                        if (c.covered) {
                            mid += c.colour;
                            ++covered;
                        }
                    }
                }
                const std::size_t at = (static_cast<std::size_t>(j) * width + static_cast<std::size_t>(s) * roomSize + i) * 4;
                for (int k = 0; k < 3; ++k) out.rooms[at + k] = linearToSrgb8(room[k] * 0.25);
                out.rooms[at + 3] = 255;
                const std::size_t local = static_cast<std::size_t>(j) * roomSize + i;
                midColour[local] = covered > 0 ? mid / static_cast<double>(covered) : dvec3(0.0);
                midCoverage[local] = covered;
                known[local] = covered > 0;
            }
        }
        // Bleed the cut-outs' colours into transparent texels (a few rings, then the mean) so that
        // bilinear filtering and mipmaps of straight alpha keep the silhouettes' edge colours.
        dvec3 mean(0.0);
        int meanCount = 0;
        for (std::size_t k = 0; k < known.size(); ++k)
            if (known[k]) {
                mean += midColour[k];
                ++meanCount;
            }
        mean = meanCount > 0 ? mean / static_cast<double>(meanCount) : dvec3(0.5);
        for (int ring = 0; ring < 8; ++ring) {
            std::vector<bool> next = known;
            for (int j = 0; j < roomSize; ++j) {
                for (int i = 0; i < roomSize; ++i) {
                    const std::size_t k = static_cast<std::size_t>(j) * roomSize + i;
                    if (known[k]) continue;
                    dvec3 sum(0.0);
                    int n = 0;
                    static constexpr int kNeighbours[4][2] = {{-1, 0}, {1, 0}, {0, -1}, {0, 1}};
                    for (const auto& d : kNeighbours) {
                        const int ni = i + d[0], nj = j + d[1];
                        if (ni < 0 || nj < 0 || ni >= roomSize || nj >= roomSize) continue;
                        const std::size_t nk = static_cast<std::size_t>(nj) * roomSize + ni;
                        if (known[nk]) {
                            sum += midColour[nk];
                            ++n;
                        }
                    }
                    if (n > 0) {
                        midColour[k] = sum / static_cast<double>(n);
                        next[k] = true;
                    }
                }
            }
            known.swap(next);
        }
        for (int j = 0; j < roomSize; ++j) {
            for (int i = 0; i < roomSize; ++i) {
                const std::size_t k = static_cast<std::size_t>(j) * roomSize + i;
                const dvec3 c = known[k] ? midColour[k] : mean;
                const std::size_t at = (static_cast<std::size_t>(j) * width + static_cast<std::size_t>(s) * roomSize + i) * 4;
                for (int ch = 0; ch < 3; ++ch) out.middle[at + ch] = linearToSrgb8(c[ch]);
                out.middle[at + 3] = static_cast<std::uint8_t>((midCoverage[k] * 255 + 2) / 4);
            }
        }
    }
    return out;
}

}  // namespace dawnforge::runtime
