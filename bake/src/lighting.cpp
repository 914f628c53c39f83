// The lighting passes (lighting.hpp): direct sky, AO, sun and lamps, then gathered bounces,
// then the room table.
#include <dawnforge/bake/lighting.hpp>
#include <dawnforge/bake/ray_scene.hpp>

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/seed.hpp>

#include <glm/geometric.hpp>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <limits>
#include <numeric>
#include <tuple>
#include <cmath>

namespace dawnforge::bake {

namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

constexpr double kPi = 3.14159265358979323846;
constexpr std::size_t kChunkTexels = 64;      // texels per work item
constexpr double kBackFaceLimit = 0.25;       // more back-face hits than this: the texel is inside something
constexpr double kDayStart = 6.0, kDayEnd = 18.0;

// Pass tags for the random streams.
enum Pass : std::uint64_t { kDirectPass = 1, kSunPass = 2, kHiddenPass = 3, kBouncePass = 16, kRoomPass = 64 };

struct TexelRef {
    std::uint32_t receiver;
    std::uint32_t sample;
};

struct Chunk {
    std::uint32_t receiver;
    std::uint32_t first, count;
};

struct ReceiverState {
    const ReceiverInput* in = nullptr;
    std::uint64_t key = 0;                  // receiverKey(name): its random streams
    glm::ivec2 size{0};
    std::vector<TexelSample> samples;
    std::vector<std::uint32_t> coarse;      // samples the bounces gather at (every other texel of each chart)
    std::vector<std::int32_t> owners;
    std::vector<glm::vec3> normal;          // per triangle, unit (CCW front)
    std::vector<float> albedo;              // per triangle
    std::vector<std::uint32_t> occluders;   // indices of the ray scene's copy
    std::vector<std::uint32_t> rayTriangle; // ray-scene triangle -> receiver triangle
    std::vector<std::uint32_t> lamps;       // lamps lighting this receiver
    std::vector<std::uint8_t> valid;        // per atlas texel: sampled and outside geometry
    std::vector<float> direct;              // per atlas texel × 3: sky, sun, lamp (dilated)
    std::vector<float> ao;                  // per atlas texel (dilated)
    std::vector<float> previous, next;      // the last bounce and the one being gathered (× 3)
    std::vector<float> bounced;             // all bounces so far (× 3)
    std::size_t invalid = 0;
    std::size_t texelCount() const { return std::size_t(size.x) * std::size_t(size.y); }
};

// Duff et al. 2017, "Building an Orthonormal Basis, Revisited".
void basis(glm::vec3 n, glm::vec3& t, glm::vec3& b) {
    const float sign = std::copysign(1.0f, n.z);
    const float a = -1.0f / (sign + n.z);
    const float c = n.x * n.y * a;
    t = glm::vec3(1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x);
    b = glm::vec3(c, sign + n.y * n.y * a, -n.y);
}

float radicalInverse(std::uint32_t i) {
    i = (i << 16u) | (i >> 16u);
    i = ((i & 0x55555555u) << 1u) | ((i & 0xAAAAAAAAu) >> 1u);
    i = ((i & 0x33333333u) << 2u) | ((i & 0xCCCCCCCCu) >> 2u);
    i = ((i & 0x0F0F0F0Fu) << 4u) | ((i & 0xF0F0F0F0u) >> 4u);
    i = ((i & 0x00FF00FFu) << 8u) | ((i & 0xFF00FF00u) >> 8u);
    return float(i) * 2.3283064365386963e-10f;
}

float fract(float x) { return x - std::floor(x); }

// Sample i of n cosine-weighted directions about (t, b, n): a Hammersley set shifted by
// (r1, r2) (Cranley–Patterson rotation, one per texel).
glm::vec3 cosineDirection(std::uint32_t i, std::uint32_t n, float r1, float r2, glm::vec3 t, glm::vec3 b, glm::vec3 normal) {
    const float u1 = fract((float(i) + 0.5f) / float(n) + r1), u2 = fract(radicalInverse(i) + r2);
    const float r = std::sqrt(u1), phi = float(2.0 * kPi) * u2;
    const float z = std::sqrt(std::max(0.0f, 1.0f - u1));
    return glm::normalize(r * std::cos(phi) * t + r * std::sin(phi) * b + z * normal);
}

// The n cosine-weighted directions of a Hammersley set in the local frame (z = normal); each
// texel turns the set about its normal by its own random angle.
std::vector<glm::vec3> cosineSet(std::uint32_t n) {
    std::vector<glm::vec3> out(n);
    for (std::uint32_t i = 0; i < n; ++i) {
        const float u1 = (float(i) + 0.5f) / float(n), u2 = radicalInverse(i);
        const float r = std::sqrt(u1), phi = float(2.0 * kPi) * u2;
        out[i] = glm::vec3(r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0f, 1.0f - u1)));
    }
    return out;
}

// A receiver's random streams follow its name, not its place in the list, so that a building
// baked with its tile's halo draws the same rays as in a bake of the whole city.
std::uint64_t receiverKey(std::string_view name) {
    std::uint64_t h = 0xcbf29ce484222325ull;  // FNV-1a
    for (char c : name) h = (h ^ std::uint8_t(c)) * 0x100000001b3ull;
    return mix64(h);
}

std::uint64_t streamSeed(std::uint64_t seed, std::uint64_t pass, std::uint64_t receiverKey, std::uint32_t texel) {
    return mix64(seed ^ mix64(pass * 0x9e3779b97f4a7c15ull ^ receiverKey ^ texel));
}

// Bilinear read of a 3-channel atlas buffer at texel coordinates (GL's convention: texel
// centres at +0.5, clamped to the edge).
glm::vec3 bilinear3(const std::vector<float>& buffer, glm::ivec2 size, glm::vec2 uv) {
    const float x = uv.x - 0.5f, y = uv.y - 0.5f;
    const float fx0 = std::floor(x), fy0 = std::floor(y);
    const float ax = x - fx0, ay = y - fy0;
    const int x0 = std::clamp(int(fx0), 0, size.x - 1), x1 = std::clamp(int(fx0) + 1, 0, size.x - 1);
    const int y0 = std::clamp(int(fy0), 0, size.y - 1), y1 = std::clamp(int(fy0) + 1, 0, size.y - 1);
    const auto at = [&](int xx, int yy) {
        const std::size_t i = 3 * (std::size_t(yy) * std::size_t(size.x) + std::size_t(xx));
        return glm::vec3(buffer[i], buffer[i + 1], buffer[i + 2]);
    };
    return (1.0f - ay) * ((1.0f - ax) * at(x0, y0) + ax * at(x1, y0)) + ay * ((1.0f - ax) * at(x0, y1) + ax * at(x1, y1));
}

// Where a hit lands in its receiver's atlas (texel coordinates).
glm::vec2 hitUv(const ReceiverState& r, const Hit& h) {
    const std::uint32_t t = r.rayTriangle[h.triangle];
    const auto& idx = r.in->indices;
    const auto& uv = r.in->layout.uv;
    return (1.0f - h.u - h.v) * uv[idx[3 * t]] + h.u * uv[idx[3 * t + 1]] + h.v * uv[idx[3 * t + 2]];
}

struct Scratch {
    std::vector<Ray> rays;            // hemisphere rays
    std::vector<Hit> hits;
    std::vector<Ray> shadow;          // sun and lamp rays
    std::vector<std::uint8_t> blocked;
    std::vector<float> weight;        // a shadow ray's unoccluded contribution
    std::vector<std::uint32_t> owner; // (texel in chunk << 1) | is-lamp
};

// Runs `work(chunk)` over all chunks in parallel, in slices so that progress can be reported
// (and work cancelled) from this thread.
template <typename F>
void forChunks(const std::vector<Chunk>& chunks, const ProgressFn& progress, double from, double to, F&& work) {
    const std::size_t slices = 50;
    const std::size_t per = std::max<std::size_t>(1, (chunks.size() + slices - 1) / slices);
    for (std::size_t first = 0; first < chunks.size(); first += per) {
        const std::size_t last = std::min(chunks.size(), first + per);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(first, last, 1),
                          [&](const tbb::blocked_range<std::size_t>& range) {
                              for (std::size_t c = range.begin(); c != range.end(); ++c) work(chunks[c]);
                          },
                          tbb::simple_partitioner());
        if (!progress(from + (to - from) * double(last) / double(chunks.size()))) throw Cancelled();
    }
}

}  // namespace

glm::dvec3 sunDirection(double hours) {
    const double phi = kPi * (hours - 6.0) / 12.0;
    const double elevation = (55.0 * kPi / 180.0) * std::sin(phi);
    return {std::cos(elevation) * std::cos(phi), std::sin(elevation), std::cos(elevation) * std::sin(phi)};
}

double lampIrradiance(glm::dvec3 lamp, glm::dvec3 point, glm::dvec3 normal) {
    const glm::dvec3 d = lamp - point;
    const double d2 = glm::dot(d, d), dist = std::sqrt(d2);
    if (dist >= kLampRange || dist <= 0.0) return 0.0;
    const glm::dvec3 dir = d / dist;
    const double cosine = glm::dot(normal, dir);
    if (cosine <= 0.0) return 0.0;
    const double t = std::clamp((dir.y + 0.2) / 0.4, 0.0, 1.0);
    const double below = t * t * (3.0 - 2.0 * t);
    const double q = dist / kLampRange;
    const double window = (1.0 - q * q * q * q) * (1.0 - q * q * q * q);
    return kLampIntensity * below * cosine * window / (d2 + kLampSoftening * kLampSoftening);
}

bool roomLampLit(std::uint32_t building, std::uint32_t room) {
    const std::uint32_t h = lowbias32(building * 7919u + room);
    return ((h >> 8u) & 255u) < 110u;
}

glm::ivec2 roomTableSize(std::uint32_t rooms) {
    if (rooms == 0) return {0, 0};
    const std::uint32_t columns = std::min<std::uint32_t>(rooms, kRoomTableColumns);
    const std::uint32_t rows = (rooms + columns - 1) / columns;
    return glm::ivec2(int(columns), int(rows)) * kChartAlign;
}

glm::ivec2 roomTexel(glm::ivec2 origin, std::uint32_t slot) {
    return origin + glm::ivec2(int(slot % kRoomTableColumns), int(slot / kRoomTableColumns)) * kChartAlign;
}

std::uint8_t encodeChannel(float value, int channel) {
    const float v = std::clamp(value / kChannelRange[std::size_t(channel)], 0.0f, 1.0f);
    return std::uint8_t(std::lround(255.0f * std::sqrt(v)));
}

float decodeChannel(std::uint8_t stored, int channel) {
    const float s = float(stored) / 255.0f;
    return s * s * kChannelRange[std::size_t(channel)];
}

void dilate(std::span<float> values, int channels, std::span<const std::uint8_t> filled, std::span<const std::int32_t> owners,
            glm::ivec2 size, std::span<const float> empty) {
    const int w = size.x, h = size.y;
    const std::size_t n = std::size_t(w) * std::size_t(h), c = std::size_t(channels);
    DAWNFORGE_ASSERT(values.size() == n * c && filled.size() == n && owners.size() == n && empty.size() == c, "sizes disagree");
    std::vector<std::uint8_t> done(filled.begin(), filled.end());
    std::vector<std::uint8_t> queued(n, 0);
    std::vector<std::uint32_t> frontier, candidates;
    const auto neighbours = [&](std::uint32_t i, auto&& f) {
        const int x = int(i % std::uint32_t(w)), y = int(i / std::uint32_t(w));
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                if (dx == 0 && dy == 0) continue;
                const int xx = x + dx, yy = y + dy;
                if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
                const std::uint32_t j = std::uint32_t(yy) * std::uint32_t(w) + std::uint32_t(xx);
                if (owners[j] == owners[i]) f(j);
            }
    };
    for (std::uint32_t i = 0; i < n; ++i) {
        if (done[i] || owners[i] == kUnowned) continue;
        bool touches = false;
        neighbours(i, [&](std::uint32_t j) { touches = touches || done[j]; });
        if (touches) candidates.push_back(i), queued[i] = 1;
    }
    std::vector<float> ring;
    while (!candidates.empty()) {
        std::sort(candidates.begin(), candidates.end());
        ring.assign(candidates.size() * c, 0.0f);
        for (std::size_t k = 0; k < candidates.size(); ++k) {
            int count = 0;
            neighbours(candidates[k], [&](std::uint32_t j) {
                if (!done[j]) return;
                for (std::size_t ch = 0; ch < c; ++ch) ring[k * c + ch] += values[j * c + ch];
                ++count;
            });
            for (std::size_t ch = 0; ch < c; ++ch) ring[k * c + ch] /= float(count);
        }
        for (std::size_t k = 0; k < candidates.size(); ++k) {
            for (std::size_t ch = 0; ch < c; ++ch) values[candidates[k] * c + ch] = ring[k * c + ch];
            done[candidates[k]] = 1;
        }
        frontier.swap(candidates);
        candidates.clear();
        for (std::uint32_t i : frontier)
            neighbours(i, [&](std::uint32_t j) {
                if (!done[j] && !queued[j]) queued[j] = 1, candidates.push_back(j);
            });
    }
    for (std::size_t i = 0; i < n; ++i)
        if (!done[i] && owners[i] != kUnowned)
            for (std::size_t ch = 0; ch < c; ++ch) values[i * c + ch] = empty[ch];
}


namespace {
std::vector<std::uint32_t> occluderIndices(const ReceiverInput& in) {
    std::vector<std::uint32_t> out;
    for (std::size_t t = 0; t < in.indices.size() / 3; ++t)
        if (in.occluder[t]) out.insert(out.end(), {in.indices[3 * t], in.indices[3 * t + 1], in.indices[3 * t + 2]});
    return out;
}
}  // namespace

std::unique_ptr<RayScene> occluderScene(std::span<const ReceiverInput> receivers) {
    std::vector<std::vector<std::uint32_t>> indices(receivers.size());
    tbb::parallel_for(std::size_t{0}, receivers.size(), [&](std::size_t r) { indices[r] = occluderIndices(receivers[r]); });
    std::vector<RayGeometry> geometries;
    for (std::size_t r = 0; r < receivers.size(); ++r) geometries.push_back({receivers[r].positions, indices[r], 1u});
    return std::make_unique<RayScene>(geometries);
}

std::vector<std::vector<std::uint8_t>> hiddenTriangles(const RayScene& scene, std::span<const ReceiverInput> receivers,
                                                       std::span<const std::vector<float>> texelMetres, int probes, std::uint64_t seed) {
    DAWNFORGE_ASSERT(texelMetres.size() == receivers.size() && probes > 0, "hiddenTriangles(): one texel array per receiver");
    // Per receiver: scene triangle -> receiver triangle, and triangle normals.
    std::vector<std::vector<std::uint32_t>> rayTriangle(receivers.size());
    std::vector<std::vector<glm::vec3>> normals(receivers.size());
    tbb::parallel_for(std::size_t{0}, receivers.size(), [&](std::size_t r) {
        const ReceiverInput& in = receivers[r];
        const std::size_t nt = in.indices.size() / 3;
        normals[r].resize(nt);
        for (std::size_t t = 0; t < nt; ++t) {
            const glm::vec3 a = in.positions[in.indices[3 * t]], b = in.positions[in.indices[3 * t + 1]], c = in.positions[in.indices[3 * t + 2]];
            const glm::vec3 n = glm::cross(b - a, c - a);
            normals[r][t] = glm::length(n) > 0.0f ? glm::normalize(n) : glm::vec3(0.0f, 1.0f, 0.0f);
            if (in.occluder[t]) rayTriangle[r].push_back(std::uint32_t(t));
        }
    });
    std::vector<std::vector<std::uint8_t>> hidden(receivers.size());
    const std::vector<glm::vec3> directions = cosineSet(std::uint32_t(probes));
    tbb::parallel_for(std::size_t{0}, receivers.size(), [&](std::size_t r) {
        const ReceiverInput& in = receivers[r];
        const std::size_t nt = in.indices.size() / 3;
        hidden[r].assign(nt, 0);
        const std::vector<float>& texel = texelMetres[r];
        // Patches: triangles sharing vertex indices.
        std::vector<std::uint32_t> parent(nt);
        for (std::uint32_t t = 0; t < nt; ++t) parent[t] = t;
        const auto find = [&](std::uint32_t x) {
            while (parent[x] != x) x = parent[x] = parent[parent[x]];
            return x;
        };
        std::vector<std::uint32_t> firstUse(in.positions.size(), std::uint32_t(-1));
        const auto probed = [&](std::uint32_t t) { return texel[t] > 0.0f && in.occluder[t]; };
        for (std::uint32_t t = 0; t < nt; ++t) {
            if (!probed(t)) continue;
            for (int k = 0; k < 3; ++k) {
                std::uint32_t& f = firstUse[in.indices[3 * std::size_t(t) + std::size_t(k)]];
                if (f == std::uint32_t(-1)) {
                    f = t;
                } else {
                    const std::uint32_t a = find(f), b = find(t);
                    if (a != b) parent[std::max(a, b)] = std::min(a, b);
                }
            }
        }
        std::vector<std::vector<std::uint32_t>> patches;
        std::vector<std::int32_t> patchOf(nt, -1);
        for (std::uint32_t t = 0; t < nt; ++t) {
            if (!probed(t)) continue;
            const std::uint32_t root = find(t);
            if (patchOf[root] < 0) patchOf[root] = std::int32_t(patches.size()), patches.emplace_back();
            patches[std::size_t(patchOf[root])].push_back(t);
        }
        std::vector<Ray> rays;
        std::vector<Hit> hits;
        std::vector<double> cumulative;
        for (const std::vector<std::uint32_t>& patch : patches) {
            cumulative.clear();
            double total = 0.0;
            for (std::uint32_t t : patch) {
                const glm::vec3 a = in.positions[in.indices[3 * t]], b = in.positions[in.indices[3 * t + 1]], c = in.positions[in.indices[3 * t + 2]];
                total += 0.5 * double(glm::length(glm::cross(b - a, c - a)));
                cumulative.push_back(total);
            }
            if (total <= 0.0) continue;
            Rng rng(streamSeed(seed, kHiddenPass, receiverKey(in.name), patch.front()));
            rays.resize(std::size_t(probes));
            hits.resize(rays.size());
            for (int k = 0; k < probes; ++k) {
                const double pick = total * (double(k) + rng.uniform()) / double(probes);
                const std::size_t i = std::min<std::size_t>(std::size_t(std::lower_bound(cumulative.begin(), cumulative.end(), pick) - cumulative.begin()), patch.size() - 1);
                const std::uint32_t t = patch[i];
                double u = rng.uniform(), v = rng.uniform();
                if (u + v > 1.0) u = 1.0 - u, v = 1.0 - v;
                const glm::vec3 a = in.positions[in.indices[3 * t]], b = in.positions[in.indices[3 * t + 1]], c = in.positions[in.indices[3 * t + 2]];
                const glm::vec3 n = normals[r][t];
                glm::vec3 tt, bb;
                basis(n, tt, bb);
                const glm::vec3 d = directions[std::size_t(k)];
                rays[std::size_t(k)].origin = a + float(u) * (b - a) + float(v) * (c - a) + n * in.rayOffset[t];
                rays[std::size_t(k)].direction = d.x * tt + d.y * bb + d.z * n;
            }
            scene.intersect(rays, hits);
            int back = 0;
            for (int k = 0; k < probes; ++k) {
                const Hit& h = hits[std::size_t(k)];
                if (h.geometry == kNoHit) continue;
                back += glm::dot(normals[h.geometry][rayTriangle[h.geometry][h.triangle]], rays[std::size_t(k)].direction) > 0.0f;
            }
            if (back >= probes - 1)
                for (std::uint32_t t : patch) hidden[r][t] = 1;
        }
    });
    return hidden;
}

namespace {

// Texel samples, coarse (bounce) samples, triangle data and buffers of one receiver.
void prepareReceiver(const ReceiverInput& in, const LightingSettings& settings, ReceiverState& s) {
    s.in = &in;
    s.key = receiverKey(in.name);
    s.size = in.layout.size;
    const std::size_t nt = in.indices.size() / 3;
    DAWNFORGE_ASSERT(in.materials.size() == nt && in.occluder.size() == nt && in.rayOffset.size() == nt,
                     "bakeLighting(): one material, occluder flag and ray offset per triangle");
    s.samples = sampleTexels(ChartMesh{in.positions, in.indices, {}}, in.layout);
    s.owners = blockOwners(in.layout);
    // Bounce light is smooth: gather it at every other texel of each chart (even offsets from
    // the block's corner) and interpolate the rest; a chart with no such texel gathers at all.
    std::vector<std::uint8_t> chartHasCoarse(in.layout.charts.size(), 0);
    const auto isCoarse = [&](std::uint32_t texel) {
        const std::int32_t c = s.owners[texel];
        if (c < 0 || c >= std::int32_t(in.layout.charts.size())) return true;
        const glm::ivec2 o = in.layout.charts[std::size_t(c)].origin;
        const int x = int(texel % std::uint32_t(s.size.x)), y = int(texel / std::uint32_t(s.size.x));
        return (x - o.x) % 2 == 0 && (y - o.y) % 2 == 0;
    };
    for (const TexelSample& ts : s.samples)
        if (isCoarse(ts.texel) && s.owners[ts.texel] >= 0 && s.owners[ts.texel] < std::int32_t(chartHasCoarse.size()))
            chartHasCoarse[std::size_t(s.owners[ts.texel])] = 1;
    for (std::uint32_t i = 0; i < s.samples.size(); ++i) {
        const std::int32_t c = s.owners[s.samples[i].texel];
        const bool lone = c >= 0 && c < std::int32_t(chartHasCoarse.size()) && !chartHasCoarse[std::size_t(c)];
        if (lone || isCoarse(s.samples[i].texel)) s.coarse.push_back(i);
    }
    s.normal.resize(nt);
    s.albedo.resize(nt);
    for (std::size_t t = 0; t < nt; ++t) {
        const glm::vec3 a = in.positions[in.indices[3 * t]], b = in.positions[in.indices[3 * t + 1]], c = in.positions[in.indices[3 * t + 2]];
        const glm::vec3 cr = glm::cross(b - a, c - a);
        const float len = glm::length(cr);
        s.normal[t] = len > 0.0f ? cr / len : glm::vec3(0.0f, 1.0f, 0.0f);
        s.albedo[t] = settings.albedo[in.materials[t] & 15u];
        if (in.occluder[t]) {
            s.rayTriangle.push_back(std::uint32_t(t));
            s.occluders.insert(s.occluders.end(), {in.indices[3 * t], in.indices[3 * t + 1], in.indices[3 * t + 2]});
        }
    }
    const std::size_t n = s.texelCount();
    s.valid.assign(n, 0);
    s.direct.assign(3 * n, 0.0f);
    s.ao.assign(n, 1.0f);
    s.bounced.assign(3 * n, 0.0f);
}

// Fills the texels between the coarse ones a bounce gathered at (weighted 3×3 neighbours of
// the same block), then dilates.
void interpolateBounce(ReceiverState& s) {
    std::vector<std::uint8_t> gathered(s.texelCount(), 0);
    for (std::uint32_t i : s.coarse) gathered[s.samples[i].texel] = s.valid[s.samples[i].texel];
    std::vector<std::uint8_t> filled = gathered;
    const int w = s.size.x, h = s.size.y;
    for (const TexelSample& ts : s.samples) {
        if (gathered[ts.texel] || !s.valid[ts.texel]) continue;
        const int x = int(ts.texel % std::uint32_t(w)), y = int(ts.texel / std::uint32_t(w));
        glm::vec3 sum(0.0f);
        float weight = 0.0f;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const int xx = x + dx, yy = y + dy;
                if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
                const std::size_t j = std::size_t(yy) * std::size_t(w) + std::size_t(xx);
                if (!gathered[j] || s.owners[j] != s.owners[ts.texel]) continue;
                const float wgt = float((2 - std::abs(dx)) * (2 - std::abs(dy)));
                sum += wgt * glm::vec3(s.next[3 * j], s.next[3 * j + 1], s.next[3 * j + 2]);
                weight += wgt;
            }
        if (weight <= 0.0f) continue;
        sum /= weight;
        for (int c = 0; c < 3; ++c) s.next[3 * std::size_t(ts.texel) + std::size_t(c)] = sum[c];
        filled[ts.texel] = 1;
    }
    dilate(s.next, 3, filled, s.owners, s.size, std::vector<float>{0.0f, 0.0f, 0.0f});
}

// The four channels of a receiver, and its room table.
void packChannels(const ReceiverState& s, ReceiverLighting& o) {
    const std::size_t n = s.texelCount();
    o.channels.assign(4 * n, 0.0f);
    for (std::size_t i = 0; i < n; ++i) {
        o.channels[4 * i] = s.direct[3 * i] + s.bounced[3 * i];
        o.channels[4 * i + 1] = s.bounced[3 * i + 1];
        o.channels[4 * i + 2] = s.ao[i];
        o.channels[4 * i + 3] = s.direct[3 * i + 2] + s.bounced[3 * i + 2];
    }
    if (s.in->rooms > 0) {
        DAWNFORGE_ASSERT(!s.in->layout.extraOrigins.empty(), "bakeLighting(): a receiver with rooms needs its room table block");
        for (std::uint32_t slot = 0; slot < s.in->rooms; ++slot) {
            const glm::ivec2 at = roomTexel(s.in->layout.extraOrigins[0], slot);
            const glm::vec3 v = o.rooms[slot];
            for (int dy = 0; dy < kChartAlign; ++dy)
                for (int dx = 0; dx < kChartAlign; ++dx) {
                    const std::size_t i = std::size_t(at.y + dy) * std::size_t(s.size.x) + std::size_t(at.x + dx);
                    o.channels[4 * i] = v.x, o.channels[4 * i + 1] = v.y, o.channels[4 * i + 2] = 1.0f, o.channels[4 * i + 3] = v.z;
                }
        }
    }
    o.texels = s.samples.size();
    for (const TexelSample& ts : s.samples) o.invalid += !s.valid[ts.texel];
}

// One bakeLighting() call: the passes share the receivers' state, the ray scene and the
// per-thread scratch buffers.
class LightingBaker {
public:
    LightingBaker(std::span<const ReceiverInput> inputs, std::span<const Lamp> lamps, std::span<const RoomWindow> windows,
                  const LightingSettings& settings, const ProgressFn& progress, const RayScene* prebuilt)
        : inputs_(inputs), lamps_(lamps), windows_(windows), settings_(settings), progress_(progress),
          state_(inputs.size()), S_(std::uint32_t(settings.samples)), directions_(cosineSet(S_)) {
        tbb::parallel_for(std::size_t{0}, inputs.size(), [&](std::size_t r) { prepareReceiver(inputs[r], settings, state_[r]); });
        std::vector<RayGeometry> geometries(inputs.size());
        for (std::size_t r = 0; r < inputs.size(); ++r) geometries[r] = RayGeometry{inputs[r].positions, state_[r].occluders, 1u};
        for (std::size_t l = 0; l < lamps.size(); ++l) {
            DAWNFORGE_ASSERT(lamps[l].receiver < inputs.size(), "bakeLighting(): a lamp's receiver is out of range");
            state_[lamps[l].receiver].lamps.push_back(std::uint32_t(l));
        }
        if (!prebuilt) own_ = std::make_unique<RayScene>(geometries);
        scene_ = prebuilt ? prebuilt : own_.get();
        DAWNFORGE_ASSERT(scene_->geometryCount() == inputs.size(), "bakeLighting(): the scene must hold one geometry per receiver");
        for (std::uint32_t r = 0; r < state_.size(); ++r) {
            out_.stats.texels += state_[r].samples.size();
            for (std::size_t f = 0; f < state_[r].samples.size(); f += kChunkTexels)
                chunks_.push_back({r, std::uint32_t(f), std::uint32_t(std::min(kChunkTexels, state_[r].samples.size() - f))});
            for (std::size_t f = 0; f < state_[r].coarse.size(); f += kChunkTexels)
                coarseChunks_.push_back({r, std::uint32_t(f), std::uint32_t(std::min(kChunkTexels, state_[r].coarse.size() - f))});
        }
    }

    Lighting run() {
        const double passes = double(2 + settings_.bounces);
        auto t0 = Clock::now();
        forChunks(chunks_, progress_, 0.0, 1.0 / passes, [&](const Chunk& chunk) { directChunk(chunk); });
        out_.stats.raySeconds += secondsSince(t0);
        dilateAll(&ReceiverState::direct, 3, {0.0f, 0.0f, 0.0f});
        dilateAll(&ReceiverState::ao, 1, {1.0f});
        for (int bounce = 1; bounce <= settings_.bounces; ++bounce) {
            for (ReceiverState& s : state_) s.next.assign(3 * s.texelCount(), 0.0f);
            t0 = Clock::now();
            forChunks(coarseChunks_, progress_, double(bounce) / passes, double(bounce + 1) / passes,
                      [&](const Chunk& chunk) { bounceChunk(chunk, bounce); });
            out_.stats.raySeconds += secondsSince(t0);
            const auto t1 = Clock::now();
            tbb::parallel_for(std::size_t{0}, state_.size(), [&](std::size_t r) { interpolateBounce(state_[r]); });
            out_.stats.dilateSeconds += secondsSince(t1);
            for (ReceiverState& s : state_) {
                for (std::size_t i = 0; i < s.bounced.size(); ++i) s.bounced[i] += s.next[i];
                s.previous.swap(s.next);
            }
        }
        for (ReceiverState& s : state_) {
            std::vector<float>().swap(s.previous);
            std::vector<float>().swap(s.next);
        }
        out_.receivers.resize(inputs_.size());
        for (std::size_t r = 0; r < inputs_.size(); ++r) out_.receivers[r].rooms.assign(inputs_[r].rooms, glm::vec3(0.0f));
        t0 = Clock::now();
        roomTable();
        out_.stats.raySeconds += secondsSince(t0);
        tbb::parallel_for(std::size_t{0}, state_.size(), [&](std::size_t r) { packChannels(state_[r], out_.receivers[r]); });
        out_.stats.rays = rayCount_.load();
        return std::move(out_);
    }

private:
    // S cosine rays from each texel of the chunk (samples `index(i)`), traced into sc.hits.
    template <typename Index>
    void hemisphere(const Chunk& chunk, std::uint64_t pass, Scratch& sc, Index&& index) const {
        const ReceiverState& s = state_[chunk.receiver];
        sc.rays.resize(std::size_t(chunk.count) * S_);
        sc.hits.resize(sc.rays.size());
        for (std::uint32_t i = 0; i < chunk.count; ++i) {
            const TexelSample& ts = s.samples[index(i)];
            Rng rng(streamSeed(settings_.seed, pass, s.key, ts.texel));
            const float angle = float(2.0 * kPi * rng.uniform());
            const float c = std::cos(angle), sn = std::sin(angle);
            glm::vec3 t, b;
            basis(ts.normal, t, b);
            const glm::vec3 tt = c * t + sn * b, bb = c * b - sn * t;  // the set turned about the normal
            const glm::vec3 origin = ts.position + ts.normal * s.in->rayOffset[ts.triangle];
            for (std::uint32_t k = 0; k < S_; ++k) {
                Ray& ray = sc.rays[std::size_t(i) * S_ + k];
                const glm::vec3 d = directions_[k];
                ray.origin = origin;
                ray.direction = d.x * tt + d.y * bb + d.z * ts.normal;
                ray.tNear = 0.0f;
                ray.tFar = std::numeric_limits<float>::infinity();
            }
        }
        scene_->intersect(sc.rays, sc.hits);
    }

    // The hit's triangle and whether the ray met its front.
    bool frontHit(const Hit& h, glm::vec3 dir, std::uint32_t& triangle) const {
        const ReceiverState& hs = state_[h.geometry];
        triangle = hs.rayTriangle[h.triangle];
        return glm::dot(hs.normal[triangle], dir) < 0.0f;
    }

    void dilateAll(std::vector<float> ReceiverState::*member, int channels, std::vector<float> empty) {
        const auto t0 = Clock::now();
        tbb::parallel_for(std::size_t{0}, state_.size(), [&](std::size_t r) {
            ReceiverState& s = state_[r];
            dilate(s.*member, channels, s.valid, s.owners, s.size, empty);
        });
        out_.stats.dilateSeconds += secondsSince(t0);
    }

    // Shadow rays of a chunk's texels: the sun at K times of the day, and the receiver's lamps.
    void shadowRays(const Chunk& chunk, Scratch& sc) const {
        const ReceiverState& s = state_[chunk.receiver];
        const std::uint32_t K = std::uint32_t(settings_.sunSamples);
        sc.shadow.clear(), sc.weight.clear(), sc.owner.clear();
        for (std::uint32_t i = 0; i < chunk.count; ++i) {
            const TexelSample& ts = s.samples[chunk.first + i];
            const glm::vec3 origin = ts.position + ts.normal * s.in->rayOffset[ts.triangle];
            Rng rng(streamSeed(settings_.seed, kSunPass, s.key, ts.texel));
            for (std::uint32_t k = 0; k < K; ++k) {
                const double hours = kDayStart + (kDayEnd - kDayStart) * (double(k) + rng.uniform()) / double(K);
                const glm::vec3 d(sunDirection(hours));
                const float cosine = glm::dot(d, ts.normal);
                if (cosine <= 0.0f) continue;
                Ray ray;
                ray.origin = origin;
                ray.direction = d;
                sc.shadow.push_back(ray);
                sc.weight.push_back(cosine / float(K));
                sc.owner.push_back(i << 1);
            }
            for (std::uint32_t l : s.lamps) {
                const glm::vec3 lamp = lamps_[l].position;
                const double e = lamps_[l].intensity * lampIrradiance(glm::dvec3(lamp), glm::dvec3(origin), glm::dvec3(ts.normal));
                if (e <= 1e-5) continue;
                Ray ray;
                ray.origin = origin;
                ray.direction = lamp - origin;  // t = 1 at the lamp; stop 2 cm short
                ray.tFar = 1.0f - 0.02f / std::max(glm::length(ray.direction), 0.04f);
                sc.shadow.push_back(ray);
                sc.weight.push_back(float(e));
                sc.owner.push_back((i << 1) | 1u);
            }
        }
    }

    // Direct: sky, AO and back faces from S cosine rays; the sun along the day; lamps.
    void directChunk(const Chunk& chunk) {
        ReceiverState& s = state_[chunk.receiver];
        Scratch& sc = scratch_.local();
        hemisphere(chunk, kDirectPass, sc, [&](std::uint32_t i) { return chunk.first + i; });
        shadowRays(chunk, sc);
        sc.blocked.resize(sc.shadow.size());
        scene_->occluded(sc.shadow, sc.blocked);
        rayCount_ += sc.rays.size() + sc.shadow.size();
        float sun[kChunkTexels] = {}, lamp[kChunkTexels] = {};
        for (std::size_t k = 0; k < sc.shadow.size(); ++k) {
            if (sc.blocked[k]) continue;
            float* light = (sc.owner[k] & 1u) ? lamp : sun;  // a pointer: UBSan misreads a conditional of arrays
            light[sc.owner[k] >> 1] += sc.weight[k];
        }
        const float aoRadius = float(settings_.aoRadius);
        for (std::uint32_t i = 0; i < chunk.count; ++i) {
            std::uint32_t sky = 0, open = 0, back = 0;
            for (std::uint32_t k = 0; k < S_; ++k) {
                const std::size_t j = std::size_t(i) * S_ + k;
                const Hit& h = sc.hits[j];
                const glm::vec3 dir = sc.rays[j].direction;
                if (h.geometry == kNoHit) {
                    ++open;
                    sky += dir.y > 0.0f;  // escaping downwards happens only past the world's edge
                    continue;
                }
                open += h.t >= aoRadius;
                std::uint32_t tri;
                back += !frontHit(h, dir, tri);
            }
            const std::uint32_t texel = s.samples[chunk.first + i].texel;
            if (double(back) > kBackFaceLimit * S_) continue;  // inside something: dilation fills it
            s.valid[texel] = 1;
            s.direct[3 * texel] = float(sky) / float(S_);
            s.direct[3 * texel + 1] = sun[i];
            s.direct[3 * texel + 2] = lamp[i];
            s.ao[texel] = float(open) / float(S_);
        }
    }

    // A bounce: the previous bounce (the direct light first) where the rays land, times the albedo.
    void bounceChunk(const Chunk& chunk, int bounce) {
        ReceiverState& s = state_[chunk.receiver];
        Scratch& sc = scratch_.local();
        hemisphere(chunk, kBouncePass + std::uint64_t(bounce), sc, [&](std::uint32_t i) { return s.coarse[chunk.first + i]; });
        rayCount_ += sc.rays.size();
        for (std::uint32_t i = 0; i < chunk.count; ++i) {
            const std::uint32_t texel = s.samples[s.coarse[chunk.first + i]].texel;
            if (!s.valid[texel]) continue;
            glm::vec3 sum(0.0f);
            for (std::uint32_t k = 0; k < S_; ++k) {
                const std::size_t j = std::size_t(i) * S_ + k;
                const Hit& h = sc.hits[j];
                std::uint32_t tri;
                if (h.geometry == kNoHit || !frontHit(h, sc.rays[j].direction, tri)) continue;
                const ReceiverState& hs = state_[h.geometry];
                sum += hs.albedo[tri] * bilinear3(bounce == 1 ? hs.direct : hs.previous, hs.size, hitUv(hs, h));
            }
            sum /= float(S_);
            for (int c = 0; c < 3; ++c) s.next[3 * std::size_t(texel) + std::size_t(c)] = sum[c];
        }
    }

    // Rooms: the irradiance (direct + bounced) of the surfaces seen through their windows.
    void roomTable() {
        std::vector<std::size_t> order(windows_.size());
        std::iota(order.begin(), order.end(), std::size_t{0});
        std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
            return std::tie(windows_[a].receiver, windows_[a].slot, a) < std::tie(windows_[b].receiver, windows_[b].slot, b);
        });
        std::vector<std::pair<std::size_t, std::size_t>> rooms;  // ranges of `order`
        for (std::size_t i = 0; i < order.size();) {
            std::size_t j = i;
            const RoomWindow& w = windows_[order[i]];
            while (j < order.size() && windows_[order[j]].receiver == w.receiver && windows_[order[j]].slot == w.slot) ++j;
            DAWNFORGE_ASSERT(w.receiver < inputs_.size() && w.slot < inputs_[w.receiver].rooms, "bakeLighting(): a window's room is out of range");
            rooms.emplace_back(i, j);
            i = j;
        }
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, rooms.size(), 1), [&](const tbb::blocked_range<std::size_t>& range) {
            for (std::size_t ri = range.begin(); ri != range.end(); ++ri) roomLevels(order, rooms[ri].first, rooms[ri].second);
        });
    }

    // One room's levels from rays cast inwards through its windows (order[first..last)).
    void roomLevels(const std::vector<std::size_t>& order, std::size_t first, std::size_t last) {
        Scratch& sc = scratch_.local();
        const RoomWindow& w0 = windows_[order[first]];
        std::vector<double> cumulative;
        double total = 0.0;
        for (std::size_t k = first; k < last; ++k) {
            const RoomWindow& w = windows_[order[k]];
            total += 0.5 * double(glm::length(glm::cross(w.b - w.a, w.c - w.a)));
            cumulative.push_back(total);
        }
        const std::uint32_t M = std::uint32_t(settings_.roomSamples);
        sc.rays.resize(M);
        sc.hits.resize(M);
        Rng rng(streamSeed(settings_.seed, kRoomPass, state_[w0.receiver].key, w0.slot));
        for (std::uint32_t j = 0; j < M; ++j) {
            const double pick = total * (double(j) + rng.uniform()) / double(M);
            const std::size_t k = std::min<std::size_t>(
                std::size_t(std::lower_bound(cumulative.begin(), cumulative.end(), pick) - cumulative.begin()), cumulative.size() - 1);
            const RoomWindow& w = windows_[order[first + k]];
            double u = rng.uniform(), v = rng.uniform();
            if (u + v > 1.0) u = 1.0 - u, v = 1.0 - v;
            const glm::vec3 p = w.a + float(u) * (w.b - w.a) + float(v) * (w.c - w.a);
            glm::vec3 t, b;
            basis(w.inward, t, b);
            Ray& ray = sc.rays[j];
            ray.origin = p + 0.02f * w.inward;
            ray.direction = cosineDirection(j, M, float(rng.uniform()), float(rng.uniform()), t, b, w.inward);
            ray.tNear = 0.0f;
            ray.tFar = std::numeric_limits<float>::infinity();
        }
        scene_->intersect(sc.rays, sc.hits);
        rayCount_ += M;
        glm::vec3 sum(0.0f);
        for (std::uint32_t j = 0; j < M; ++j) {
            const Hit& h = sc.hits[j];
            std::uint32_t tri;
            if (h.geometry == kNoHit || !frontHit(h, sc.rays[j].direction, tri)) continue;
            const ReceiverState& hs = state_[h.geometry];
            const glm::vec2 uv = hitUv(hs, h);
            sum += bilinear3(hs.direct, hs.size, uv) + bilinear3(hs.bounced, hs.size, uv);
        }
        out_.receivers[w0.receiver].rooms[w0.slot] = sum / float(M);
    }

    std::span<const ReceiverInput> inputs_;
    std::span<const Lamp> lamps_;
    std::span<const RoomWindow> windows_;
    const LightingSettings& settings_;
    const ProgressFn& progress_;
    std::vector<ReceiverState> state_;
    std::uint32_t S_;
    std::vector<glm::vec3> directions_;
    std::unique_ptr<RayScene> own_;
    const RayScene* scene_ = nullptr;
    std::vector<Chunk> chunks_, coarseChunks_;
    tbb::enumerable_thread_specific<Scratch> scratch_;
    std::atomic<std::size_t> rayCount_{0};
    Lighting out_;
};

}  // namespace

Lighting bakeLighting(std::span<const ReceiverInput> inputs, std::span<const Lamp> lamps, std::span<const RoomWindow> windows,
                      const LightingSettings& settings, const ProgressFn& progress, const RayScene* prebuilt) {
    DAWNFORGE_ASSERT(settings.samples > 0 && settings.sunSamples > 0 && settings.bounces >= 0 && settings.roomSamples > 0,
                     "bakeLighting(): sample counts must be positive");
    LightingBaker baker(inputs, lamps, windows, settings, progress, prebuilt);
    return baker.run();
}

}  // namespace dawnforge::bake
