// The building texture atlas: block layout, the wrap/LOD arithmetic the shader mirrors
// (shaders/atlas.glsl), and the procedural material tiles.
//
// Determinism: every texel is a pure function of its position (integer hashes, no shared
// state, no reductions), so the result does not depend on the thread count; build with
// -ffp-contract=off like the rest of dawnforge so float expressions round the same way.
#include <dawnforge/runtime/atlas.hpp>

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/materials.hpp>
#include <dawnforge/core/seed.hpp>

#include <glm/common.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace dawnforge::runtime {

namespace {

constexpr int kHalfCell = kAtlasCell / 2;
constexpr int kCellsPerRow = kAtlasSize / kAtlasCell;

// Brick and plaster cells hold four half-size colour variants.
bool hasHalfVariants(int material) { return material == kBrick || material == kPlaster; }

void checkBlock(AtlasBlock b) {
    DAWNFORGE_ASSERT(b.slot >= 0 && b.slot < 16, "slot must be 0..15");
    DAWNFORGE_ASSERT(b.quadrant >= -1 && b.quadrant < 4, "quadrant must be -1..3");
}

struct TexelSquare {
    glm::ivec2 origin;  // level-0 texels
    int size = 0;
};

TexelSquare cellTexels(AtlasBlock b) {
    checkBlock(b);
    TexelSquare cell{{b.slot % kCellsPerRow * kAtlasCell, b.slot / kCellsPerRow * kAtlasCell}, kAtlasCell};
    if (b.quadrant >= 0) {
        cell.origin += glm::ivec2(b.quadrant % 2, b.quadrant / 2) * kHalfCell;
        cell.size = kHalfCell;
    }
    return cell;
}

TexelSquare interiorTexels(AtlasBlock b) {
    TexelSquare cell = cellTexels(b);
    return {cell.origin + kAtlasPadding, cell.size - 2 * kAtlasPadding};
}

AtlasRect toUv(TexelSquare s) {
    return {glm::dvec2(s.origin) / double(kAtlasSize), glm::dvec2(s.size) / double(kAtlasSize)};
}

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

std::uint8_t toByte(float x) { return std::uint8_t(std::clamp(int(x * 255.0f + 0.5f), 0, 255)); }

// ---- Layout of the generated atlas --------------------------------------------------------

struct PlacedBlock {
    AtlasBlock block;
    int material = 0, variant = 0;
};

std::vector<PlacedBlock> atlasLayout() {
    std::vector<PlacedBlock> blocks;
    for (int material = 0; material < kMaterialCount; ++material) {
        if (hasHalfVariants(material))
            for (int variant = 0; variant < 4; ++variant) blocks.push_back({materialBlock(material, variant), material, variant});
        else
            blocks.push_back({materialBlock(material, 0), material, 0});
    }
    return blocks;
}

// ---- sRGB ⇄ linear for the mip chain ------------------------------------------------------

struct SrgbTables {
    std::array<std::uint16_t, 256> toLinear{};     // sRGB8 → linear · 65535
    std::vector<std::uint8_t> fromLinear;          // linear · 65535 → nearest sRGB8
};

double srgbToLinear(double s) { return s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4); }
double linearToSrgb(double l) { return l <= 0.0031308 ? l * 12.92 : 1.055 * std::pow(l, 1.0 / 2.4) - 0.055; }

const SrgbTables& srgbTables() {
    static const SrgbTables tables = [] {
        SrgbTables t;
        for (int k = 0; k < 256; ++k) t.toLinear[k] = std::uint16_t(std::lround(srgbToLinear(k / 255.0) * 65535.0));
        t.fromLinear.resize(65536);
        for (int x = 0; x < 65536; ++x) t.fromLinear[x] = std::uint8_t(std::lround(linearToSrgb(x / 65535.0) * 255.0));
        return t;
    }();
    return tables;
}

void downsample(const std::vector<std::uint8_t>& src, int srcSize, std::vector<std::uint8_t>& dst) {
    const int size = srcSize / 2;
    dst.assign(std::size_t(size) * size * 4, 0);
    const SrgbTables& t = srgbTables();
    tbb::parallel_for(tbb::blocked_range<int>(0, size, 16), [&](const tbb::blocked_range<int>& rows) {
        for (int y = rows.begin(); y < rows.end(); ++y)
            for (int x = 0; x < size; ++x) {
                const std::uint8_t* a = &src[(std::size_t(2 * y) * srcSize + 2 * x) * 4];
                const std::uint8_t* b = a + std::size_t(srcSize) * 4;
                std::uint8_t* out = &dst[(std::size_t(y) * size + x) * 4];
                for (int c = 0; c < 3; ++c) {
                    const unsigned sum = t.toLinear[a[c]] + t.toLinear[a[c + 4]] + t.toLinear[b[c]] + t.toLinear[b[c + 4]];
                    out[c] = t.fromLinear[(sum + 2) / 4];
                }
                out[3] = std::uint8_t((a[3] + a[7] + b[3] + b[7] + 2) / 4);
            }
    });
}

}  // namespace

std::uint32_t encodeBlock(AtlasBlock b) {
    checkBlock(b);
    if (b.quadrant < 0) return std::uint32_t(b.slot);
    return std::uint32_t(b.slot) | (1U << 4) | (std::uint32_t(b.quadrant) << 5);
}

AtlasBlock decodeBlock(std::uint32_t code) {
    const bool half = (code >> 4 & 1U) != 0;
    return {int(code & 15U), half ? int(code >> 5 & 3U) : -1};
}

AtlasRect blockInterior(AtlasBlock b) { return toUv(interiorTexels(b)); }

AtlasRect blockCell(AtlasBlock b) { return toUv(cellTexels(b)); }

double materialTileMetres(int material) {
    static constexpr double kTile[kMaterialCount] = {
        4.0,  // asphalt
        2.0,  // paving: 0.5 m slabs
        2.0,  // brick: 30 courses of 6.7 cm, 8 bricks of 25 cm
        3.0,  // concrete: 1.5 m panels
        3.0,  // plaster
        2.0,  // glass
        2.0,  // metal: 0.25 m ribs
        1.0,  // trim
        2.0,  // roof tiles: 0.25 m rows
        4.0,  // flat roof gravel
        2.0,  // wood: 0.125 m boards
        3.0,  // interior wall
        2.0,  // floor: 0.4 m tiles
        4.0,  // ground
        4.0,  // sand
        2.0,  // rubble: 20 cm chunks
    };
    DAWNFORGE_ASSERT(material >= 0 && material < kMaterialCount, "material must be 0..15");
    return kTile[material];
}

AtlasBlock materialBlock(int material, int variant) {
    DAWNFORGE_ASSERT(material >= 0 && material < kMaterialCount, "material must be 0..15");
    DAWNFORGE_ASSERT(variant >= 0 && variant < 4, "variant must be 0..3");
    return hasHalfVariants(material) ? AtlasBlock{material, variant} : AtlasBlock{material, -1};
}

glm::dvec2 atlasUv(AtlasBlock b, glm::dvec2 uvMetres, double tileMetres) {
    const AtlasRect r = blockInterior(b);
    const glm::dvec2 t = uvMetres / tileMetres;
    return r.origin + (t - glm::floor(t)) * r.size;
}

double atlasLod(AtlasBlock b, glm::dvec2 dUvMetresDx, glm::dvec2 dUvMetresDy, double tileMetres) {
    const double texelsPerMetre = blockInterior(b).size.x / tileMetres * kAtlasSize;
    const double rho = std::max(std::hypot(dUvMetresDx.x, dUvMetresDx.y), std::hypot(dUvMetresDy.x, dUvMetresDy.y)) * texelsPerMetre;
    if (!(rho > 1.0)) return 0.0;
    return std::min(std::log2(rho), double(kAtlasLevels - 1));
}

TexelBox sampleFootprint(glm::dvec2 uv, double lod, int maxLevel) {
    DAWNFORGE_ASSERT(maxLevel >= 0 && (kAtlasSize >> maxLevel) >= 1, "maxLevel out of range");
    const int first = int(std::clamp(std::floor(lod), 0.0, double(maxLevel)));
    const int levels[2] = {first, std::min(first + 1, maxLevel)};
    TexelBox box{glm::ivec2(kAtlasSize * 2), glm::ivec2(-kAtlasSize * 2)};
    for (int level : levels) {
        const double size = double(kAtlasSize >> level);
        const int scale = 1 << level;
        const glm::ivec2 i(int(std::floor(uv.x * size - 0.5)), int(std::floor(uv.y * size - 0.5)));
        box.min = glm::min(box.min, i * scale);
        box.max = glm::max(box.max, (i + 2) * scale);
    }
    return box;
}

AtlasImage generateAtlas() {
    AtlasImage image;
    std::vector<std::uint8_t>& level0 = image.rgba[0];
    level0.assign(std::size_t(kAtlasSize) * kAtlasSize * 4, 255);

    // 1. Each block's tile at its interior resolution, one task per group of rows.
    const std::vector<PlacedBlock> blocks = atlasLayout();
    std::vector<std::vector<std::uint8_t>> tiles(blocks.size());
    std::vector<int> firstRow(blocks.size() + 1, 0);
    for (std::size_t k = 0; k < blocks.size(); ++k) {
        const int n = interiorTexels(blocks[k].block).size;
        tiles[k].resize(std::size_t(n) * n * 3);
        firstRow[k + 1] = firstRow[k] + n;
    }
    tbb::parallel_for(tbb::blocked_range<int>(0, firstRow.back(), 8), [&](const tbb::blocked_range<int>& rows) {
        for (int r = rows.begin(); r < rows.end(); ++r) {
            const std::size_t k = std::size_t(std::upper_bound(firstRow.begin(), firstRow.end(), r) - firstRow.begin() - 1);
            const int n = firstRow[k + 1] - firstRow[k], j = r - firstRow[k];
            const float v = (float(j) + 0.5f) / float(n);
            std::uint8_t* out = &tiles[k][std::size_t(j) * n * 3];
            for (int i = 0; i < n; ++i) {
                const Rgb c = paintTile(blocks[k].material, blocks[k].variant, (float(i) + 0.5f) / float(n), v);
                out[3 * i] = toByte(c.r);
                out[3 * i + 1] = toByte(c.g);
                out[3 * i + 2] = toByte(c.b);
            }
        }
    });

    // Each tile's mean in linear light, summed in a fixed order.
    const SrgbTables& srgb = srgbTables();
    for (std::size_t k = 0; k < blocks.size(); ++k) {
        double sum[3] = {0.0, 0.0, 0.0};
        for (std::size_t t = 0; t < tiles[k].size(); ++t) sum[t % 3] += srgb.toLinear[tiles[k][t]];
        const double n = double(tiles[k].size() / 3) * 65535.0;
        image.blockMean[encodeBlock(blocks[k].block)] = glm::vec4(float(sum[0] / n), float(sum[1] / n), float(sum[2] / n), 1.0f);
    }

    // 2. Fill every cell, interior and padding, from the tile at the wrapped position.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks.size()), [&](const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t k = range.begin(); k < range.end(); ++k) {
            const TexelSquare cell = cellTexels(blocks[k].block);
            const int n = cell.size - 2 * kAtlasPadding;
            for (int y = 0; y < cell.size; ++y) {
                const std::uint8_t* row = &tiles[k][std::size_t(wrapIndex(y - kAtlasPadding, n)) * n * 3];
                std::uint8_t* out = &level0[(std::size_t(cell.origin.y + y) * kAtlasSize + cell.origin.x) * 4];
                for (int x = 0; x < cell.size; ++x) {
                    const std::uint8_t* texel = row + wrapIndex(x - kAtlasPadding, n) * 3;
                    out[4 * x] = texel[0];
                    out[4 * x + 1] = texel[1];
                    out[4 * x + 2] = texel[2];
                }
            }
        }
    });

    // 3. The mip chain, box-filtered in linear light.
    for (int level = 1; level < kAtlasLevels; ++level) downsample(image.rgba[level - 1], kAtlasSize >> (level - 1), image.rgba[level]);
    return image;
}

}  // namespace dawnforge::runtime
