// Contact damage on a bond graph: a blow damages the bonds near where it lands, and the damage
// spreads from there along the bonds, not through empty space (Houdini's glue constraint
// network, NVIDIA Blast's damage with per-bond health; our own rules below).
//
// A blow is an impulse J (N·s) on a piece: the contacts of one substep on it, summed, less what
// the piece's unbroken links carry over the substep at their strength (Σ σ·A · dt): a load they
// hold, such as rubble resting on a floor, is the stress model's and no damage. What is left goes
// out through the piece's unbroken links in proportion to their areas (a wide bond takes more,
// as it is stiffer), and each link it crosses takes what crossed it as damage. The piece at the
// far end passes `transmission` of what reached it on through its links that lead further away
// (the rest its inertia takes), up to `hops` links from the piece struck; the ground passes
// nothing on. Damage accumulates, and halves every `halfLife` seconds (an old crack closes: a
// wall leaned on is not a wall hit). A link breaks when its damage exceeds its capacity, the
// force it carries at its strength (σ·A) times the impact time: a blow is as damaging as a
// force J / impactTime held for that long. So a heavy blow breaches where a light one chips,
// weak bonds near the blow go before strong ones far away, and a second blow breaks more.
// Plain data: no Bullet here.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace dawnforge::sim {

struct DamageLink {
    std::uint32_t a = 0, b = 0;  // nodes
    double area = 0.0;           // m²
    double force = 0.0;          // N: what it carries at its strength, σ·A
};

struct DamageRules {
    double transmission = 0.35; // of the impulse that reached a piece, what it passes on
    int hops = 3;               // links from the piece struck that a blow reaches
    double halfLife = 1.0;      // s: accumulated damage halves in this time
    double impactTime = 0.01;   // s: a link breaks when its damage exceeds force · impactTime
};

class DamageModel {
public:
    // `ground`: a node that takes damage on its links but passes nothing on (nodes.size() is its index + 1).
    DamageModel(std::size_t nodes, std::uint32_t ground, std::vector<DamageLink> links, DamageRules rules);

    // J (N·s, its magnitude) struck on `node` in the step being taken.
    void strike(std::uint32_t node, double impulse);
    // Ages the damage by `dt` (the step's length), spreads the step's blows and forgets them.
    // Returns the unbroken links whose damage now exceeds their capacity, in link order (the
    // caller breaks them).
    std::vector<std::size_t> spread(double dt);
    // A broken link takes and passes on nothing from now on.
    void breakLink(std::size_t link) { broken_[link] = true; }

    double damage(std::size_t link) const { return damage_[link]; }
    const std::vector<double>& damages() const { return damage_; }
    // The damage of every link as damages() gave it (a step taken again starts from there).
    void restore(const std::vector<double>& damage) { damage_ = damage; }

private:
    std::size_t nodes_;
    std::uint32_t ground_;
    std::vector<DamageLink> links_;
    DamageRules rules_;
    std::vector<std::vector<std::uint32_t>> nodeLinks_;  // per node: its links, ascending
    std::vector<bool> broken_;
    std::vector<double> damage_;  // per link, N·s
    std::vector<double> struck_;  // per node, this step's blows
};

}  // namespace dawnforge::sim
