#pragma once
// Ray queries for the bake: a static scene of triangle meshes (Embree 3 inside, never in this
// header), closest-hit and occlusion queries over batches of rays (Embree ray streams,
// rtcIntersect1M / rtcOccluded1M). The BVH is built on one thread, so the same meshes give
// the same hierarchy, hence the same hits (ties included), whatever the caller's thread count;
// queries are thread-safe and run on the calling thread.
#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>

namespace dawnforge::bake {

// One mesh of the scene; `mask` is matched against Ray::mask (a ray sees a geometry when
// mask & ray.mask != 0), so one scene can answer "buildings only" or "ground only" queries.
struct RayGeometry {
    std::span<const glm::vec3> positions;
    std::span<const std::uint32_t> indices;  // three per triangle
    std::uint32_t mask = 1;
};

inline constexpr std::uint32_t kNoHit = std::numeric_limits<std::uint32_t>::max();

struct Ray {
    glm::vec3 origin{0.0f};
    glm::vec3 direction{0.0f, 1.0f, 0.0f};  // need not be unit; t is in units of its length
    float tNear = 0.0f;
    float tFar = std::numeric_limits<float>::infinity();
    std::uint32_t mask = 0xffffffffu;
};

struct Hit {
    float t = std::numeric_limits<float>::infinity();
    std::uint32_t geometry = kNoHit;  // index into the scene's geometries; kNoHit: the ray escaped
    std::uint32_t triangle = 0;       // triangle index within that geometry
    float u = 0.0f, v = 0.0f;         // barycentrics: p = (1-u-v)·a + u·b + v·c
};

class RayScene {
public:
    // Builds the BVH (single-threaded, medium quality: Debian's Embree 3.13.5 crashes building this scene at high quality). Geometries with no triangles
    // are kept as empty slots, so geometry indices always match the input's.
    explicit RayScene(std::span<const RayGeometry> geometries);
    ~RayScene();
    RayScene(const RayScene&) = delete;
    RayScene& operator=(const RayScene&) = delete;

    void intersect(std::span<const Ray> rays, std::span<Hit> hits) const;
    // blocked[i] = 1 when something lies on ray i between tNear and tFar.
    void occluded(std::span<const Ray> rays, std::span<std::uint8_t> blocked) const;

    std::size_t triangleCount() const;
    std::size_t geometryCount() const;

    struct Impl;
    const Impl& impl() const { return *impl_; }

private:
    std::unique_ptr<Impl> impl_;
};

// Embree's raw throughput on `scene`: `rays` incoherent rays (origins on random triangles,
// directions uniform on the sphere, seeded by `seed`) made up front, then traced as
// closest-hit streams of `batch` rays by every core (TBB), nothing else done per ray. The
// ceiling the bake's own rate is measured against (bench/bake_bench.cpp).
struct RayThroughput {
    std::size_t rays = 0;
    double seconds = 0.0;     // wall
    double cpuSeconds = 0.0;  // the process's CPU time over the same span (all threads)
    double raysPerSecond = 0.0;
    double raysPerCpuSecond = 0.0;  // what a busy machine still measures fairly
    double hitFraction = 0.0;
};

// CPU time of the whole process so far (all threads), seconds.
double processCpuSeconds();
RayThroughput measureRayThroughput(const RayScene& scene, std::span<const RayGeometry> geometries, std::size_t rays,
                                   std::uint64_t seed = 1, std::size_t batch = 256);

}  // namespace dawnforge::bake
