#pragma once
// Debris: where glue breaks, chips of the broken faces' material fly out of the crack, and dust (the
// Houdini habit of a debris source on the constraint network's broken group). A second,
// cheap pass after the pieces' simulation (sim/src/debris.cpp emits, debris_motion.cpp
// moves): chips are small convex bodies that collide with the ground, the colliders and the
// moving pieces but not with each other, and sleep like the rest. Until its bond breaks a
// chip rides inside the crack with one of the bond's two pieces, hidden; the pieces' motion
// is never changed by them.
#include <cstddef>

namespace dawnforge::sim {

struct DebrisSettings {
    bool chips = false;                // the library's default; `dawnforge simulate` turns them on
    double chipsPerSquareMetre = 8.0;  // of broken bond area, for masonry (glass 2x, wood 0.5x, metal 0.2x)
    int maxChipsPerBond = 6;
    std::size_t maxChips = 1000;       // in all; the earliest breaks emit first
    double chipSize = 0.12;            // m: a chip's mean length (glass and metal chips are smaller)
    double spraySpeed = 2.5;           // m/s: the mean speed out of the crack, over the pieces' own
    // Dust: puffs that leave the crack with a little of its pieces' speed, rise, spread and fade
    // (sim/src/dust.cpp; no collisions but the ground plane).
    bool dust = false;                 // the library's default; `dawnforge simulate` turns it on
    double puffsPerSquareMetre = 4.0;  // of broken bond area, for masonry (glass 0.2x, wood 0.5x, metal none)
    std::size_t maxPuffs = 600;        // in all; the earliest breaks emit first
    double puffSize = 1.0;             // m: a puff's diameter when it leaves the crack; it grows to four times that
    double puffLife = 5.0;             // s: the mean time until it has faded out
};

}  // namespace dawnforge::sim
