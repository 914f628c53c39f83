#pragma once
// Real-time irradiance probes on the GPU (issue 14), private to the renderer. Every frame:
//   place    lattice probes of the preset's spacing in the lighting area around the player
//            (probe_placement.hpp: near geometry, outside the proxy boxes, nearest first);
//   admit    the ones the cache does not hold yet, at most the frame's budget (the farthest held
//            probe makes room when the cache is full);
//   capture  in batches of kProbeBatch: a compute pass culls the proxy boxes per cube face into
//            indirect draws, one instanced draw per face renders the flat-coloured boxes into a
//            small G-buffer (albedo, normal, distance; the clear is the sky), and a compute pass
//            lights it (sun with the shadow map, sky, street lamps at night, the probes already
//            there for the second bounce) and projects it into SH L2, storing the probe's 5 × 5 cache tile;
//   inject   the lighting area's cells → cache tiles, a small 3D index texture that every lit
//            surface reads (probe_light.glsl).
#include "flares.hpp"
#include "gl.hpp"

#include <dawnforge/runtime/probe_math.hpp>
#include <dawnforge/runtime/probe_placement.hpp>
#include <dawnforge/runtime/renderer.hpp>
#include <dawnforge/runtime/scene_file.hpp>

#include <glm/glm.hpp>

#include <memory>
#include <span>
#include <vector>

namespace dawnforge::runtime {

inline constexpr int kProbeBatch = 16;

class ProbeGpu {
public:
    ProbeGpu();
    ~ProbeGpu();
    // `boxes`: the bake's proxies. `movingBoxes`: the most boxes update() will be given (the
    // destruction pieces). `preset` null: probes off (empty resources stay bound so that
    // shaders read "none").
    // `lamps`: the city's street lamps, which light the captured surfaces at night.
    void load(std::vector<ProbeBox> boxes, int movingBoxes, std::vector<StreetLamp> lamps, const ProbePreset* preset,
              const ProbeSettings& settings);
    bool enabled() const;
    // Replaces the proxies and the lamps (a world's: those of the tiles drawn now, in render
    // space) and empties the cache: what it held was captured from the others.
    void setScene(std::vector<ProbeBox> boxes, std::vector<StreetLamp> lamps);
    // Binds the cache, the index and the Probes block for the shaders (units 11, 12; UBO 3).
    void bind() const;
    // Places, captures (at most `budget` probes; 0: all the area wants) and injects around
    // `focus`; the capture sees the proxies and the `moving` boxes. The Frame block, the
    // shadow map and the overlook depth must be bound.
    ProbeStats update(glm::dvec3 focus, int budget, std::span<const ProbeBox> moving);
    // Buildings gone from the scene (replaced by their destruction): their proxies are not
    // captured from now on; the others are again.
    void setGoneBuildings(std::span<const int> gone);
    std::vector<CapturedProbe> captured() const;
    // The debug view: a sphere at each injected probe, shaded by its irradiance, into the bound
    // framebuffer with its depth test. Returns the draw calls (0 or 1).
    std::size_t drawSpheres() const;

private:
    struct State;
    std::unique_ptr<State> s_;
};

}  // namespace dawnforge::runtime
