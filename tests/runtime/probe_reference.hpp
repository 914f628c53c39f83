#pragma once
// The probes' ground truth (issue 14): irradiance at a point from oriented, flat-coloured boxes,
// traced with Embree on the CPU; shares nothing with the runtime's capture. A hit is lit as
// probe_project.comp lights its G-buffer on the first bounce: albedo × (sun × n·l × a shadow ray
// + the sky/ground hemisphere term); a miss sees the sky of common.glsl's skyColor().
#include <dawnforge/runtime/sky.hpp>

#include <embree3/rtcore.h>
#include <glm/glm.hpp>
#include <glm/gtc/constants.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace dawnforge::test {

// An oriented box: centre, unit axes, half sizes along them, and one albedo per face in the
// order +axis0, -axis0, +axis1, -axis1, +axis2, -axis2.
struct ReferenceBox {
    glm::dvec3 centre{0.0};
    std::array<glm::dvec3, 3> axes{glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1)};
    glm::dvec3 half{0.0};
    std::array<glm::dvec3, 6> colours{};
};

class ProbeReference {
public:
    explicit ProbeReference(std::vector<ReferenceBox> boxes) : boxes_(std::move(boxes)) {
        device_ = rtcNewDevice(nullptr);
        scene_ = rtcNewScene(device_);
        RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12, boxes_.size() * 24));
        auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 12, boxes_.size() * 12));
        unsigned vertex = 0, tri = 0;
        for (const ReferenceBox& b : boxes_)
            for (int face = 0; face < 6; ++face) {
                const int a = face / 2, s = (a + 1) % 3, t = (a + 2) % 3;
                const double side = face % 2 == 0 ? 1.0 : -1.0;
                const double corner[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
                for (int k = 0; k < 4; ++k) {
                    const glm::dvec3 p = b.centre + b.axes[std::size_t(a)] * (side * b.half[a]) +
                                         b.axes[std::size_t(s)] * (corner[k][0] * b.half[s]) +
                                         b.axes[std::size_t(t)] * (corner[k][1] * b.half[t]);
                    for (int i = 0; i < 3; ++i) v[3 * (vertex + unsigned(k)) + unsigned(i)] = float(p[i]);
                }
                const unsigned q[6] = {0, 1, 2, 0, 2, 3};
                for (int i = 0; i < 6; ++i) idx[3 * tri + unsigned(i)] = vertex + q[i];
                vertex += 4;
                tri += 2;
            }
        rtcCommitGeometry(g);
        rtcAttachGeometry(scene_, g);
        rtcReleaseGeometry(g);
        rtcCommitScene(scene_);
    }
    ~ProbeReference() {
        rtcReleaseScene(scene_);
        rtcReleaseDevice(device_);
    }
    ProbeReference(const ProbeReference&) = delete;
    ProbeReference& operator=(const ProbeReference&) = delete;

    // Irradiance at p for normal n from `directions` uniform directions (a Fibonacci sphere).
    glm::dvec3 irradiance(glm::dvec3 p, glm::dvec3 n, const runtime::Lighting& light, int directions) const {
        glm::dvec3 sum(0.0);
        for (int i = 0; i < directions; ++i) {
            const double z = 1.0 - (2.0 * i + 1.0) / directions, r = std::sqrt(1.0 - z * z), phi = i * 2.399963229728653;
            const glm::dvec3 d(r * std::cos(phi), z, r * std::sin(phi));
            const double cosine = glm::dot(d, n);
            if (cosine > 0.0) sum += radiance(p, d, light) * cosine;
        }
        return sum * (4.0 * glm::pi<double>() / directions);
    }

private:
    std::vector<ReferenceBox> boxes_;
    RTCDevice device_;
    RTCScene scene_;

    static glm::dvec3 sky(glm::dvec3 d, const runtime::Lighting& l) {
        const double up = std::clamp(d.y, -1.0, 1.0);
        glm::dvec3 c = glm::mix(l.horizon, l.zenith, std::pow(std::max(up, 0.0), 0.55));
        if (up < 0.0) c = glm::mix(l.horizon, l.ground, std::clamp(-up * 3.0, 0.0, 1.0));
        const double s = std::max(glm::dot(d, l.sunDirection), 0.0);
        return c + l.sunColor * (0.35 * std::pow(s, 8.0) + 0.25 * std::pow(s, 64.0));
    }

    glm::dvec3 radiance(glm::dvec3 p, glm::dvec3 d, const runtime::Lighting& l) const {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        RTCRayHit rh{};
        rh.ray.org_x = float(p.x), rh.ray.org_y = float(p.y), rh.ray.org_z = float(p.z);
        rh.ray.dir_x = float(d.x), rh.ray.dir_y = float(d.y), rh.ray.dir_z = float(d.z);
        rh.ray.tnear = 0.0f;
        rh.ray.tfar = std::numeric_limits<float>::infinity();
        rh.ray.mask = 0xffffffffu;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene_, &context, &rh);
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return sky(d, l);
        const ReferenceBox& box = boxes_[rh.hit.primID / 12];
        const int face = int(rh.hit.primID % 12) / 2;
        const glm::dvec3 n = box.axes[std::size_t(face / 2)] * (face % 2 == 0 ? 1.0 : -1.0);
        const glm::dvec3 hit = p + d * double(rh.ray.tfar);
        const double ndl = std::max(glm::dot(n, l.sunDirection), 0.0);
        const glm::dvec3 hemi = glm::mix(l.ground, 0.5 * (l.zenith + l.horizon), n.y * 0.5 + 0.5) * 0.9;
        return box.colours[std::size_t(face)] * (l.sunColor * ndl * lit(hit + n * 1e-3, l.sunDirection) + hemi);
    }

    double lit(glm::dvec3 p, glm::dvec3 towards) const {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        RTCRay ray{};
        ray.org_x = float(p.x), ray.org_y = float(p.y), ray.org_z = float(p.z);
        ray.dir_x = float(towards.x), ray.dir_y = float(towards.y), ray.dir_z = float(towards.z);
        ray.tnear = 0.0f;
        ray.tfar = std::numeric_limits<float>::infinity();
        ray.mask = 0xffffffffu;
        rtcOccluded1(scene_, &context, &ray);
        return ray.tfar < 0.0f ? 0.0 : 1.0;
    }
};

}  // namespace dawnforge::test
