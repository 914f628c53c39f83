// The stresses in a glued structure from a linear elastic model of its bond graph.
//
// A rigid solver's joint impulses do not say how a structure carries a load: over redundant
// joints the split is arbitrary, and it swings whenever the solver starts again (a structure
// woken by a hit re-solves, and slivers a few mm² wide read 1e16 Pa). Here each piece is a
// node with six degrees of freedom (a small translation and rotation) and each bond a spring
// as stiff as it is wide: axial and shear stiffness ∝ A, bending and torsion ∝ A·r²/4 (a round
// section of the bond's area A and radius r). Nodes resting on the ground are held. The
// loads split between bonds in proportion to their stiffness, as in an elastic body, so a
// sliver carries next to nothing and the answer is the same every time (NVIDIA Blast's stress
// solver works on the same idea). Each group of nodes joined by unbroken links is its own
// system: Eigen's sparse LDLᵀ factors a group's stiffness once per set of its links, and each
// evaluation is one solve per group loaded. Eigen stays inside bond_stress.cpp.
#pragma once

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <span>
#include <vector>

namespace dawnforge::sim {

struct StressNode {
    glm::dvec3 position{0.0};  // centre of mass at rest
    double mass = 0.0;
    bool held = false;         // resting on the ground or a support: does not move
    glm::dmat3 inertia{0.0};   // about the centre of mass, in the rest frame
};

struct StressLink {
    std::uint32_t a = 0, b = 0;
    glm::dvec3 point{0.0};   // the bond's centroid at rest
    glm::dvec3 normal{0.0};  // unit, from a to b, at rest
    double area = 0.0;       // m²
    double modulus = 1.0;    // relative stiffness per area (the glue's strength: brittle materials
                             // break at much the same strain, so a weak bond is as much softer)
};

// Force and torque (about the node's rest centre of mass) on each node, in the rest frame.
struct NodeLoads {
    std::vector<glm::dvec3> force, torque;
};

class BondStressModel {
public:
    BondStressModel(std::vector<StressNode> nodes, std::vector<StressLink> links);
    ~BondStressModel();
    BondStressModel(const BondStressModel&) = delete;
    BondStressModel& operator=(const BondStressModel&) = delete;

    // A broken link carries nothing from now on (its group is factored again when next solved).
    void breakLink(std::size_t link);

    // Each link's largest principal stress under the loads (0 for a broken link): the
    // normal stress at the section's most stretched edge, pull plus bending (F·n/A + 4·M_b/(A·r)),
    // with the shear of the shear force and the torsion (|F_t|/A + 2·M_t/(A·r)), of a round
    // section of the link's area A and radius r. Brittle materials fail where it exceeds their
    // strength (Rankine); a bond only pressed reads 0. A group
    // of nodes joined by links with no held node is balanced by its own inertia (the rigid
    // motion its loads give it, linear and angular, is taken out of them) and held at its
    // first node, which then carries nothing.
    // Groups are independent: with `active` (per node), only the groups with an active node
    // are solved, and the links of the others read 0.
    std::vector<double> stresses(const NodeLoads& loads, const std::vector<bool>* active = nullptr);

private:
    struct Factor;
    void group();
    std::unique_ptr<Factor> factor(std::uint32_t root) const;
    struct RigidMotion {
        glm::dvec3 centre{0.0}, linear{0.0}, angular{0.0};  // centre of mass, its acceleration, the angular one
    };
    RigidMotion motion(std::uint32_t root, const NodeLoads& loads) const;
    void solve(std::uint32_t root, const NodeLoads& loads, std::vector<double>& out);

    std::vector<StressNode> nodes_;
    std::vector<StressLink> links_;
    std::vector<std::vector<std::uint32_t>> nodeLinks_;  // per node: the links with it as `a`
    std::vector<bool> broken_;
    bool grouped_ = false;                               // group_ and members_ are up to date
    std::vector<std::uint32_t> group_;                   // per node: the smallest node index of its group
    std::vector<std::vector<std::uint32_t>> members_;    // per group root: its nodes, ascending
    std::map<std::uint32_t, std::unique_ptr<Factor>> factors_;  // per group root, while its links are unchanged
};

}  // namespace dawnforge::sim
