// The procedural material tiles (material_paint.hpp): periodic noise and one painter per material.
#include <dawnforge/core/material_paint.hpp>

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/materials.hpp>
#include <dawnforge/core/seed.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>

namespace dawnforge {

namespace {

// ---- Periodic noise ---------------------------------------------------------------------

std::uint32_t hash(int x, int y, std::uint32_t seed) {
    return lowbias32(std::uint32_t(x) * 0x9e3779b1U + std::uint32_t(y) * 0x85ebca77U + seed * 0xc2b2ae3dU);
}

float unitHash(int x, int y, std::uint32_t seed) { return float(hash(x, y, seed) >> 8) * (1.0f / 16777216.0f); }

int wrapIndex(int i, int period) {
    int r = i % period;
    return r < 0 ? r + period : r;
}

// wrapIndex for i ∈ [−period, 2·period), without a division: lattice indices of tile coordinates.
int wrapNear(int i, int period) { return i < 0 ? i + period : (i >= period ? i - period : i); }

float fractf(float x) { return x - std::floor(x); }

// sin(2π·t) to within 0.001, from float arithmetic alone: libm's sinf picks FMA or non-FMA code by
// CPU and need not round the same everywhere.
float sinTurns(float t) {
    const float f = t - std::floor(t);
    const float y = f < 0.5f ? 16.0f * f * (0.5f - f) : -16.0f * (f - 0.5f) * (1.0f - f);
    return 0.225f * (y * std::abs(y) - y) + y;
}

float smooth(float t) { return t * t * (3.0f - 2.0f * t); }

float smoothstepf(float e0, float e1, float x) { return smooth(std::clamp((x - e0) / (e1 - e0), 0.0f, 1.0f)); }

// Value noise in [0,1] on a lattice that repeats every periodX × periodY cells; (x, y) in
// lattice units, so x = u · periodX over a tile u ∈ [0,1) repeats with the tile.
float valueNoise(float x, float y, int periodX, int periodY, std::uint32_t seed) {
    const float fx = std::floor(x), fy = std::floor(y);
    const int ix = int(fx), iy = int(fy);
    const int x0 = wrapNear(ix, periodX), x1 = wrapNear(ix + 1, periodX);
    const int y0 = wrapNear(iy, periodY), y1 = wrapNear(iy + 1, periodY);
    const float tx = smooth(x - fx), ty = smooth(y - fy);
    const float a = unitHash(x0, y0, seed), b = unitHash(x1, y0, seed);
    const float c = unitHash(x0, y1, seed), d = unitHash(x1, y1, seed);
    const float top = a + (b - a) * tx, bottom = c + (d - c) * tx;
    return top + (bottom - top) * ty;
}

// Fractal sum over tile coordinates (u, v) ∈ [0,1): octave k has period << k; result in [0,1].
float fbm(float u, float v, int period, int octaves, std::uint32_t seed) {
    float sum = 0.0f, amplitude = 1.0f, total = 0.0f;
    for (int k = 0; k < octaves; ++k) {
        const int p = period << k;
        sum += amplitude * valueNoise(u * float(p), v * float(p), p, p, seed + std::uint32_t(k) * 101U);
        total += amplitude;
        amplitude *= 0.5f;
    }
    return sum / total;
}

struct Rgb {
    float r = 0, g = 0, b = 0;
};
Rgb operator*(Rgb c, float s) { return {c.r * s, c.g * s, c.b * s}; }
Rgb mix(Rgb a, Rgb b, float t) { return {a.r + (b.r - a.r) * t, a.g + (b.g - a.g) * t, a.b + (b.b - a.b) * t}; }

// Nearest and second-nearest distance to jittered points of a periodic grid×grid lattice, and
// the nearest point's wrapped cell (for per-chunk colours).
struct Voronoi {
    float d1 = 1e9f, d2 = 1e9f;
    int cellX = 0, cellY = 0;
    float offsetX = 0, offsetY = 0;  // from the nearest point to (u, v), lattice units
};
Voronoi voronoi(float u, float v, int grid, std::uint32_t seed) {
    const float x = u * float(grid), y = v * float(grid);
    const int ix = int(std::floor(x)), iy = int(std::floor(y));
    Voronoi out;
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            const int cx = wrapNear(ix + dx, grid), cy = wrapNear(iy + dy, grid);
            const float px = float(ix + dx) + 0.15f + 0.7f * unitHash(cx, cy, seed);
            const float py = float(iy + dy) + 0.15f + 0.7f * unitHash(cx, cy, seed + 7U);
            const float d = std::sqrt((px - x) * (px - x) + (py - y) * (py - y));
            if (d < out.d1) {
                out.d2 = out.d1;
                out.d1 = d;
                out.cellX = cx;
                out.cellY = cy;
                out.offsetX = x - px;
                out.offsetY = y - py;
            } else if (d < out.d2) {
                out.d2 = d;
            }
        }
    return out;
}

// ---- Material tiles ---------------------------------------------------------------------
// Each painter maps tile coordinates (u along the wall or plan x, v up or plan y; both in
// [0,1) per tile repeat) to an sRGB colour; everything is periodic in u and v with period 1.

Rgb paintAsphalt(float u, float v) {
    const Rgb base{0.24f, 0.24f, 0.25f};
    const float grain = fbm(u, v, 32, 4, 11U) - 0.5f;
    const float stains = fbm(u, v, 4, 2, 12U) - 0.5f;
    const float speck = unitHash(int(u * 320.0f), int(v * 320.0f), 13U);
    float shade = 1.0f + 0.25f * grain + 0.15f * stains;
    if (speck > 0.92f) shade += 0.35f;
    else if (speck < 0.06f) shade -= 0.25f;
    return base * shade;
}

Rgb paintPaving(float u, float v) {  // 0.5 m slabs, 4 × 4 per 2 m tile
    const float x = u * 4.0f, y = v * 4.0f;
    const int ix = int(x), iy = int(y);
    const float fx = x - float(ix), fy = y - float(iy);
    const float edge = std::min(std::min(fx, 1.0f - fx), std::min(fy, 1.0f - fy));
    if (edge < 0.012f) return {0.33f, 0.32f, 0.30f};
    const float tint = 0.9f + 0.2f * unitHash(ix, iy, 21U);
    const float noise = fbm(u, v, 16, 4, 22U) - 0.5f;
    const float bevel = 0.85f + 0.15f * smoothstepf(0.012f, 0.04f, edge);
    return Rgb{0.70f, 0.63f, 0.55f} * (tint * bevel * (1.0f + 0.18f * noise));
}

Rgb paintBrick(float u, float v, int variant) {  // 30 courses × 8 bricks per 2 m, running bond
    static constexpr Rgb kBrick[4] = {
        {0.56f, 0.25f, 0.17f}, {0.40f, 0.21f, 0.17f}, {0.77f, 0.63f, 0.42f}, {0.68f, 0.67f, 0.64f}};
    static constexpr Rgb kMortar[4] = {
        {0.71f, 0.69f, 0.65f}, {0.60f, 0.58f, 0.55f}, {0.60f, 0.57f, 0.52f}, {0.47f, 0.46f, 0.45f}};
    const float y = v * 30.0f;
    const int row = int(y);
    const float x = u * 8.0f + (row % 2 == 1 ? 0.5f : 0.0f);
    const int col = int(x);
    const float fx = x - float(col), fy = y - float(row);
    const float noise = fbm(u, v, 32, 3, 31U + std::uint32_t(variant)) - 0.5f;
    if (fy < 0.15f || fx < 0.04f) return kMortar[variant] * (1.0f + 0.2f * noise);
    const int brickX = wrapIndex(col, 8);
    const float tint = 0.82f + 0.3f * unitHash(brickX, row, 33U + std::uint32_t(variant));
    const float burn = unitHash(brickX, row, 34U + std::uint32_t(variant));
    Rgb c = kBrick[variant] * (tint * (1.0f + 0.25f * noise));
    if (burn > 0.85f) c = c * 0.75f;  // the odd dark-fired brick
    return c;
}

Rgb paintConcrete(float u, float v) {  // 1.5 m panels, 2 × 2 per 3 m tile, with form-tie holes
    const float x = u * 2.0f, y = v * 2.0f;
    const float fx = fractf(x), fy = fractf(y);
    const float joint = std::min(std::min(fx, 1.0f - fx), std::min(fy, 1.0f - fy));
    const float blotch = fbm(u, v, 6, 4, 41U) - 0.5f;
    const float grain = valueNoise(u * 384.0f, v * 384.0f, 384, 384, 42U) - 0.5f;
    Rgb c = Rgb{0.61f, 0.61f, 0.59f} * (1.0f + 0.22f * blotch + 0.08f * grain);
    if (joint < 0.005f) return c * 0.6f;
    const float hx = fractf(x * 3.0f) - 0.5f, hy = fractf(y * 3.0f) - 0.5f;  // 3 × 3 ties per panel
    const float r = std::sqrt(hx * hx + hy * hy);
    if (r < 0.025f) return c * 0.45f;
    if (r < 0.045f) return c * 0.85f;
    return c;
}

Rgb paintPlaster(float u, float v, int variant) {
    static constexpr Rgb kPlaster[4] = {
        {0.87f, 0.85f, 0.79f}, {0.86f, 0.74f, 0.51f}, {0.80f, 0.54f, 0.44f}, {0.62f, 0.70f, 0.75f}};
    const std::uint32_t s = 51U + std::uint32_t(variant) * 10U;
    const float fine = fbm(u, v, 24, 4, s) - 0.5f;
    const float stains = fbm(u, v, 3, 3, s + 1U);
    const float shade = 1.0f + 0.08f * fine - 0.07f * smoothstepf(0.55f, 0.8f, stains);
    return kPlaster[variant] * shade;
}

Rgb paintGlass(float u, float v) {  // dark blue-grey with soft diagonal sheen bands
    const float sheen = sinTurns(u + v);
    const float clouds = fbm(u, v, 3, 3, 61U) - 0.5f;
    return Rgb{0.15f, 0.20f, 0.26f} * (1.0f + 0.12f * sheen + 0.25f * clouds);
}

Rgb paintMetal(float u, float v) {  // painted standing-seam steel: ribs every 0.25 m
    const float phase = fractf(u * 8.0f);
    const float rib = phase < 0.05f ? 1.25f : 0.95f + 0.1f * sinTurns(0.5f * phase);
    const float streak = valueNoise(u * 128.0f, v * 4.0f, 128, 4, 71U) - 0.5f;
    const float weather = fbm(u, v, 4, 3, 72U) - 0.5f;
    return Rgb{0.34f, 0.37f, 0.41f} * (rib * (1.0f + 0.12f * streak + 0.15f * weather));
}

Rgb paintTrim(float u, float v) {  // limestone bands and sills: fine grain, faint bedding lines
    const float grain = fbm(u, v, 16, 4, 81U) - 0.5f;
    const float bedding = valueNoise(u * 2.0f, v * 48.0f, 2, 48, 82U) - 0.5f;
    const float speck = unitHash(int(u * 240.0f), int(v * 240.0f), 83U);
    float shade = 1.0f + 0.1f * grain + 0.05f * bedding;
    if (speck > 0.95f) shade -= 0.08f;
    return Rgb{0.79f, 0.75f, 0.65f} * shade;
}

Rgb paintRoofTiles(float u, float v) {  // clay pantiles: 8 rows × 8 tiles per 2 m, offset rows
    const float y = v * 8.0f;
    const int row = int(y);
    const float x = u * 8.0f + (row % 2 == 1 ? 0.5f : 0.0f);
    const int col = int(x);
    const float fx = x - float(col), fy = y - float(row);
    const float tint = 0.85f + 0.25f * unitHash(wrapIndex(col, 8), row, 91U);
    const float curve = 0.8f + 0.25f * sinTurns(0.5f * fx);
    const float overlap = 0.7f + 0.3f * smoothstepf(0.0f, 0.25f, fy);  // shadow of the row above
    const float noise = fbm(u, v, 16, 3, 92U) - 0.5f;
    float shade = tint * curve * overlap * (1.0f + 0.2f * noise);
    if (fx < 0.025f || fx > 0.975f) shade *= 0.55f;
    return Rgb{0.66f, 0.31f, 0.20f} * shade;
}

Rgb paintFlatRoof(float u, float v) {  // gravel ballast
    const float pebbles = valueNoise(u * 200.0f, v * 200.0f, 200, 200, 101U) - 0.5f;
    const float grit = unitHash(int(u * 480.0f), int(v * 480.0f), 102U) - 0.5f;
    const float patches = fbm(u, v, 4, 3, 103U) - 0.5f;
    const float tone = unitHash(int(u * 200.0f), int(v * 200.0f), 104U);
    const Rgb base = mix(Rgb{0.47f, 0.46f, 0.44f}, Rgb{0.50f, 0.44f, 0.37f}, tone);
    return base * (1.0f + 0.45f * pebbles + 0.2f * grit + 0.15f * patches);
}

Rgb paintWood(float u, float v) {  // vertical boards 0.125 m wide, one butt joint per board and tile
    const float x = u * 16.0f;
    const int board = int(x);
    const float fx = x - float(board);
    const float butt = unitHash(board, 0, 111U);
    const float jv = fractf(v - butt);
    const float tint = 0.85f + 0.3f * unitHash(board, 1, 112U);
    const float warp = valueNoise(u * 64.0f, v * 4.0f, 64, 4, 113U);
    const float rings = 0.5f + 0.5f * sinTurns(fx * 3.0f + 2.0f * warp);
    const float grain = valueNoise(u * 256.0f, v * 8.0f, 256, 8, 114U) - 0.5f;
    float shade = tint * (0.85f + 0.2f * rings + 0.2f * grain);
    if (fx < 0.04f || jv < 0.004f || jv > 0.996f) shade *= 0.45f;
    return Rgb{0.50f, 0.33f, 0.19f} * shade;
}

Rgb paintInteriorWall(float u, float v) {  // emulsion paint with roller texture
    const float roller = valueNoise(u * 24.0f, v * 96.0f, 24, 96, 121U) - 0.5f;
    const float fine = fbm(u, v, 64, 2, 122U) - 0.5f;
    return Rgb{0.90f, 0.89f, 0.86f} * (1.0f + 0.025f * roller + 0.03f * fine);
}

Rgb paintFloor(float u, float v) {  // 0.4 m stone tiles in two tones, 5 × 5 per 2 m
    const float x = u * 5.0f, y = v * 5.0f;
    const int ix = int(x), iy = int(y);
    const float fx = x - float(ix), fy = y - float(iy);
    const float edge = std::min(std::min(fx, 1.0f - fx), std::min(fy, 1.0f - fy));
    if (edge < 0.008f) return {0.30f, 0.28f, 0.26f};
    // 5 is odd, so a checkerboard would not repeat: tone by hash instead.
    const bool dark = unitHash(ix, iy, 131U) < 0.5f;
    const Rgb tone = dark ? Rgb{0.52f, 0.45f, 0.37f} : Rgb{0.72f, 0.66f, 0.56f};
    const float veins = fbm(u, v, 10, 4, 132U + (dark ? 1U : 0U)) - 0.5f;
    return tone * (1.0f + 0.2f * veins);
}

Rgb paintGround(float u, float v) {  // grass with patches of bare earth
    const float patch = fbm(u, v, 4, 3, 141U);
    const float earthMix = smoothstepf(0.52f, 0.68f, patch);
    const float blades = unitHash(int(u * 480.0f), int(v * 480.0f), 142U) - 0.5f;
    const float clumps = fbm(u, v, 48, 3, 143U) - 0.5f;
    const Rgb grass = Rgb{0.29f, 0.42f, 0.17f} * (1.0f + 0.3f * blades + 0.35f * clumps);
    const Rgb earth = Rgb{0.43f, 0.34f, 0.24f} * (1.0f + 0.15f * blades + 0.25f * clumps);
    return mix(grass, earth, earthMix);
}

Rgb paintSand(float u, float v) {  // fine sand with wind ripples
    const float wobble = fbm(u, v, 4, 2, 151U);
    const float ripple = sinTurns(u * 14.0f + v * 6.0f + 1.5f * wobble);
    const float grain = unitHash(int(u * 480.0f), int(v * 480.0f), 152U) - 0.5f;
    const float tone = fbm(u, v, 6, 3, 153U) - 0.5f;
    return Rgb{0.80f, 0.72f, 0.55f} * (1.0f + 0.04f * ripple + 0.08f * grain + 0.1f * tone);
}

Rgb paintRubble(float u, float v) {  // fracture faces: faceted chunks of concrete and brick in dust
    const Voronoi chunk = voronoi(u, v, 14, 161U);
    const float kind = unitHash(chunk.cellX, chunk.cellY, 162U);
    const Rgb base = kind < 0.6f    ? Rgb{0.55f, 0.54f, 0.52f}
                     : kind < 0.8f  ? Rgb{0.50f, 0.30f, 0.23f}
                                    : Rgb{0.60f, 0.55f, 0.46f};
    // Each chunk is a tilted facet: shade varies linearly across it in a random direction.
    const float angle = unitHash(chunk.cellX, chunk.cellY, 163U);  // turns
    const float facet = 0.85f + 0.25f * unitHash(chunk.cellX, chunk.cellY, 164U) +
                        0.35f * (sinTurns(angle + 0.25f) * chunk.offsetX + sinTurns(angle) * chunk.offsetY);
    const float grit = fbm(u, v, 48, 3, 165U) - 0.5f;
    const float dust = smoothstepf(0.42f, 0.7f, fbm(u, v, 5, 4, 166U));
    const float width = 0.03f + 0.12f * valueNoise(u * 24.0f, v * 24.0f, 24, 24, 167U);  // cracks open and close
    const float crack = smoothstepf(0.0f, width, chunk.d2 - chunk.d1);
    const Rgb c = base * (facet * (1.0f + 0.35f * grit) * (0.3f + 0.7f * crack));
    return mix(c, Rgb{0.62f, 0.58f, 0.52f} * (1.0f + 0.3f * grit), 0.8f * dust);
}

Rgb paintTile(int material, int variant, float u, float v) {
    switch (material) {
        case kAsphalt: return paintAsphalt(u, v);
        case kPaving: return paintPaving(u, v);
        case kBrick: return paintBrick(u, v, variant);
        case kConcrete: return paintConcrete(u, v);
        case kPlaster: return paintPlaster(u, v, variant);
        case kGlass: return paintGlass(u, v);
        case kMetal: return paintMetal(u, v);
        case kTrim: return paintTrim(u, v);
        case kRoofTiles: return paintRoofTiles(u, v);
        case kRoofFlat: return paintFlatRoof(u, v);
        case kWood: return paintWood(u, v);
        case kInteriorWall: return paintInteriorWall(u, v);
        case kFloor: return paintFloor(u, v);
        case kGround: return paintGround(u, v);
        case kSand: return paintSand(u, v);
        default: return paintRubble(u, v);
    }
}

}  // namespace

bool materialHasVariants(int material) { return material == kBrick || material == kPlaster; }

glm::vec3 paintMaterial(int material, int variant, float u, float v) {
    DAWNFORGE_ASSERT(material >= 0 && material < kMaterialCount, "material must be 0..15");
    DAWNFORGE_ASSERT(variant >= 0 && variant < 4, "variant must be 0..3");
    const Rgb c = paintTile(material, variant, u, v);
    return {c.r, c.g, c.b};
}

int materialVariant(std::uint32_t buildingId, int material) {
    DAWNFORGE_ASSERT(material >= 0 && material < kMaterialCount, "material must be 0..15");
    if (!materialHasVariants(material)) return 0;
    const std::uint64_t h = deriveSeed(0x6174'6c61'7300ull, "atlas variant", buildingId);
    return int((h >> (2 * material)) & 3u);
}

std::uint32_t variantBuilding(std::string_view meshName) {
    constexpr std::string_view kPrefix = "building_";
    if (!meshName.starts_with(kPrefix) || meshName.size() == kPrefix.size()) return 0xffffu;
    std::uint32_t id = 0;
    for (char c : meshName.substr(kPrefix.size())) {
        if (c < '0' || c > '9') break;
        id = id * 10u + std::uint32_t(c - '0');
    }
    return std::isdigit(static_cast<unsigned char>(meshName[kPrefix.size()])) ? id : 0xffffu;
}

}  // namespace dawnforge
