// The bake's ray scene on Embree 3 (the only file that includes Embree).
#include <dawnforge/bake/ray_scene.hpp>

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/seed.hpp>

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <glm/geometric.hpp>

#include <atomic>
#include <chrono>
#include <ctime>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace dawnforge::bake {

struct RayScene::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    std::size_t triangles = 0;
    std::size_t geometries = 0;
    std::string error;  // the first message Embree reported
    ~Impl() {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }
};

namespace {

// Embree calls this from C code: note the first message, and check after each call that can fail.
void errorHandler(void* user, RTCError code, const char* message) {
    auto* first = static_cast<std::string*>(user);
    if (code != RTC_ERROR_NONE && first->empty()) *first = message ? message : "error " + std::to_string(int(code));
}

void checkDevice(RTCDevice device, const std::string& message, const char* what) {
    if (rtcGetDeviceError(device) != RTC_ERROR_NONE || !message.empty())
        throw std::runtime_error(std::string("Embree: ") + what + ": " + message);
}

constexpr std::size_t kChunk = 256;  // rays converted and traced per stream call

void toEmbree(const Ray& r, RTCRayHit& e) {
    e.ray.org_x = r.origin.x, e.ray.org_y = r.origin.y, e.ray.org_z = r.origin.z;
    e.ray.dir_x = r.direction.x, e.ray.dir_y = r.direction.y, e.ray.dir_z = r.direction.z;
    e.ray.tnear = r.tNear;
    e.ray.tfar = r.tFar;
    e.ray.time = 0.0f;
    e.ray.mask = r.mask;
    e.ray.id = 0;
    e.ray.flags = 0;
    e.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    e.hit.primID = RTC_INVALID_GEOMETRY_ID;
    e.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

}  // namespace

RayScene::RayScene(std::span<const RayGeometry> geometries) : impl_(std::make_unique<Impl>()) {
    Impl& s = *impl_;
    s.device = rtcNewDevice("verbose=0");
    if (!s.device) throw std::runtime_error("Embree: cannot create a device (error " + std::to_string(int(rtcGetDeviceError(nullptr))) + ")");
    rtcSetDeviceErrorFunction(s.device, errorHandler, &s.error);
    s.scene = rtcNewScene(s.device);
    // Robust traversal: no cracks between the triangles of a closed wall for light to leak through.
    rtcSetSceneFlags(s.scene, RTC_SCENE_FLAG_ROBUST);
    s.geometries = geometries.size();
    for (std::size_t g = 0; g < geometries.size(); ++g) {
        const RayGeometry& in = geometries[g];
        DAWNFORGE_ASSERT(in.indices.size() % 3 == 0, "index count must be a multiple of 3");
        const std::size_t tris = in.indices.size() / 3;
        RTCGeometry geom = rtcNewGeometry(s.device, RTC_GEOMETRY_TYPE_TRIANGLE);
        // Embree reads 16 bytes from the last vertex: one float of slack.
        auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                              3 * sizeof(float), std::max<std::size_t>(in.positions.size(), 1)));
        for (std::size_t i = 0; i < in.positions.size(); ++i) {
            v[3 * i] = in.positions[i].x, v[3 * i + 1] = in.positions[i].y, v[3 * i + 2] = in.positions[i].z;
        }
        if (in.positions.empty()) v[0] = v[1] = v[2] = 0.0f;
        auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                   3 * sizeof(unsigned), tris));
        for (std::size_t i = 0; i < in.indices.size(); ++i) {
            DAWNFORGE_ASSERT(in.indices[i] < in.positions.size(), "index out of range");
            idx[i] = in.indices[i];
        }
        rtcSetGeometryMask(geom, in.mask);
        rtcCommitGeometry(geom);
        // Empty geometries keep their slot (ID = input index) but are disabled.
        rtcAttachGeometryByID(s.scene, geom, unsigned(g));
        if (tris == 0) rtcDisableGeometry(geom);
        rtcReleaseGeometry(geom);
        s.triangles += tris;
    }
    // One thread builds: the same BVH for any caller's thread count (README, Determinism).
    tbb::task_arena single(1);
    single.execute([&] { rtcCommitScene(s.scene); });
    checkDevice(s.device, s.error, "building the ray scene");
}

RayScene::~RayScene() = default;

std::size_t RayScene::triangleCount() const { return impl_->triangles; }
std::size_t RayScene::geometryCount() const { return impl_->geometries; }

void RayScene::intersect(std::span<const Ray> rays, std::span<Hit> hits) const {
    DAWNFORGE_ASSERT(rays.size() == hits.size(), "one hit per ray");
    alignas(64) RTCRayHit buffer[kChunk];
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    for (std::size_t first = 0; first < rays.size(); first += kChunk) {
        const std::size_t n = std::min(kChunk, rays.size() - first);
        for (std::size_t i = 0; i < n; ++i) toEmbree(rays[first + i], buffer[i]);
        rtcIntersect1M(impl_->scene, &context, buffer, unsigned(n), sizeof(RTCRayHit));
        for (std::size_t i = 0; i < n; ++i) {
            const RTCRayHit& e = buffer[i];
            Hit& h = hits[first + i];
            if (e.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
                h = Hit{};
            } else {
                h.t = e.ray.tfar;
                h.geometry = e.hit.geomID;
                h.triangle = e.hit.primID;
                h.u = e.hit.u;
                h.v = e.hit.v;
            }
        }
    }
}

void RayScene::occluded(std::span<const Ray> rays, std::span<std::uint8_t> blocked) const {
    DAWNFORGE_ASSERT(rays.size() == blocked.size(), "one answer per ray");
    alignas(64) RTCRay buffer[kChunk];
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    for (std::size_t first = 0; first < rays.size(); first += kChunk) {
        const std::size_t n = std::min(kChunk, rays.size() - first);
        for (std::size_t i = 0; i < n; ++i) {
            RTCRayHit e;
            toEmbree(rays[first + i], e);
            buffer[i] = e.ray;
        }
        rtcOccluded1M(impl_->scene, &context, buffer, unsigned(n), sizeof(RTCRay));
        // An occluded ray's tfar becomes -inf.
        for (std::size_t i = 0; i < n; ++i) blocked[first + i] = buffer[i].tfar < 0.0f ? 1 : 0;
    }
}

double processCpuSeconds() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

RayThroughput measureRayThroughput(const RayScene& scene, std::span<const RayGeometry> geometries, std::size_t rays,
                                   std::uint64_t seed, std::size_t batch) {
    DAWNFORGE_ASSERT(batch > 0, "batch must be positive");
    // Random triangles by index over all geometries, origins at random barycentrics nudged off
    // the surface, directions uniform on the sphere: as incoherent as rays get.
    std::vector<std::pair<std::size_t, std::size_t>> triangles;
    for (std::size_t g = 0; g < geometries.size(); ++g)
        for (std::size_t t = 0; t < geometries[g].indices.size() / 3; ++t) triangles.emplace_back(g, t);
    DAWNFORGE_ASSERT(!triangles.empty(), "the scene has no triangles");
    std::vector<RTCRayHit> prepared(rays);
    Rng rng(seed);
    for (RTCRayHit& e : prepared) {
        const auto [g, t] = triangles[rng.below(triangles.size())];
        const RayGeometry& geo = geometries[g];
        const glm::vec3 a = geo.positions[geo.indices[3 * t]], b = geo.positions[geo.indices[3 * t + 1]],
                        c = geo.positions[geo.indices[3 * t + 2]];
        double u = rng.uniform(), v = rng.uniform();
        if (u + v > 1.0) u = 1.0 - u, v = 1.0 - v;
        const glm::vec3 p = a + float(u) * (b - a) + float(v) * (c - a);
        const double z = 2.0 * rng.uniform() - 1.0, phi = 2.0 * 3.14159265358979 * rng.uniform();
        const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
        Ray ray;
        ray.direction = glm::vec3(float(r * std::cos(phi)), float(z), float(r * std::sin(phi)));
        ray.origin = p;
        ray.tNear = 1e-3f;
        toEmbree(ray, e);
    }
    const std::size_t chunks = (rays + batch - 1) / batch;
    std::atomic<std::size_t> hitCount{0};
    const auto t0 = std::chrono::steady_clock::now();
    const double cpu0 = processCpuSeconds();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunks, 1), [&](const tbb::blocked_range<std::size_t>& range) {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        context.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
        std::size_t local = 0;
        for (std::size_t c = range.begin(); c != range.end(); ++c) {
            const std::size_t first = c * batch, n = std::min(batch, rays - first);
            rtcIntersect1M(scene.impl().scene, &context, prepared.data() + first, unsigned(n), sizeof(RTCRayHit));
            for (std::size_t i = 0; i < n; ++i) local += prepared[first + i].hit.geomID != RTC_INVALID_GEOMETRY_ID;
        }
        hitCount += local;
    });
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double cpu = processCpuSeconds() - cpu0;
    return {rays,
            seconds,
            cpu,
            double(rays) / std::max(seconds, 1e-9),
            double(rays) / std::max(cpu, 1e-9),
            double(hitCount.load()) / double(std::max<std::size_t>(rays, 1))};
}

}  // namespace dawnforge::bake
