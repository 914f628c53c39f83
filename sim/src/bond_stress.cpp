// The only Eigen translation unit of sim: the bond graph's stiffness, factored with a
// sparse LDLᵀ (bond_stress.hpp says why a linear model).
#include "bond_stress.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/union_find.hpp>

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include <algorithm>
#include <stdexcept>

namespace dawnforge::sim {

namespace {

using Vector = Eigen::VectorXd;
using Link12 = Eigen::Matrix<double, 12, 12>;
using Jacobian = Eigen::Matrix<double, 3, 12>;

// [r]ₓ: the matrix of v ↦ r × v.
Eigen::Matrix3d crossMatrix(const glm::dvec3& r) {
    Eigen::Matrix3d m;
    m << 0.0, -r.z, r.y, r.z, 0.0, -r.x, -r.y, r.x, 0.0;
    return m;
}

double radiusOf(double area) { return std::sqrt(area / 3.14159265358979323846); }

// The bond's stiffness: translation ∝ E·A, rotation ∝ E·A·r²/4 (E the link's modulus, L = 1:
// only the ratios matter, the forces a load makes do not depend on the scale).
struct Stiffness {
    double translation, rotation;
};
Stiffness stiffnessOf(const StressLink& l) {
    const double r = radiusOf(l.area);
    return {l.modulus * l.area, l.modulus * l.area * r * r / 4.0};
}

// Relative displacement at the bond point (node a's side minus node b's) and relative
// rotation, as linear maps of [t_a θ_a t_b θ_b].
std::pair<Jacobian, Jacobian> jacobians(const StressLink& l, const std::vector<StressNode>& nodes) {
    Jacobian jt = Jacobian::Zero(), jr = Jacobian::Zero();
    const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
    jt.block<3, 3>(0, 0) = I;
    jt.block<3, 3>(0, 3) = -crossMatrix(l.point - nodes[l.a].position);
    jt.block<3, 3>(0, 6) = -I;
    jt.block<3, 3>(0, 9) = crossMatrix(l.point - nodes[l.b].position);
    jr.block<3, 3>(0, 3) = I;
    jr.block<3, 3>(0, 9) = -I;
    return {jt, jr};
}

// The largest principal stress of a round section of the link's area under a force pulling
// b away from a along the normal (and shearing it across) and a moment (bending about an axis
// across the normal, twisting about it). Pressed sections with no shear give 0.
double principalStress(const StressLink& l, const glm::dvec3& force, const glm::dvec3& moment) {
    const double r = radiusOf(l.area);
    const double pull = glm::dot(force, l.normal), twist = glm::dot(moment, l.normal);
    const double bending = glm::length(moment - twist * l.normal), shearForce = glm::length(force - pull * l.normal);
    const double sigma = pull / l.area + 4.0 * bending / (l.area * r);
    const double tau = shearForce / l.area + 2.0 * std::abs(twist) / (l.area * r);
    return 0.5 * sigma + std::sqrt(0.25 * sigma * sigma + tau * tau);
}

}  // namespace

struct BondStressModel::Factor {
    std::vector<int> local;  // per member of the group: its first row
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt;
};

BondStressModel::BondStressModel(std::vector<StressNode> nodes, std::vector<StressLink> links)
    : nodes_(std::move(nodes)), links_(std::move(links)), nodeLinks_(nodes_.size()), broken_(links_.size(), false) {
    for (std::size_t i = 0; i < links_.size(); ++i) {
        const StressLink& l = links_[i];
        if (l.a >= nodes_.size() || l.b >= nodes_.size() || l.a == l.b || !(l.area > 0.0))
            throw InputError("bond stress model: a bond joins missing pieces, a piece to itself, or has no area");
        nodeLinks_[l.a].push_back(std::uint32_t(i));
    }
}

BondStressModel::~BondStressModel() = default;

void BondStressModel::breakLink(std::size_t link) {
    if (broken_[link]) return;
    broken_[link] = true;
    if (!group_.empty()) factors_.erase(group_[links_[link].a]);  // the root of its group when last grouped
    grouped_ = false;
}

// Groups: union-find over the unbroken links, the smallest index first. A group that no
// link break touched keeps its root, and so its factor.
void BondStressModel::group() {
    const std::size_t n = nodes_.size();
    UnionFind groups(n);
    for (std::size_t i = 0; i < links_.size(); ++i)
        if (!broken_[i]) groups.unite(links_[i].a, links_[i].b);
    group_.resize(n);
    members_.assign(n, {});
    for (std::size_t i = 0; i < n; ++i) {
        group_[i] = groups.find(std::uint32_t(i));
        members_[group_[i]].push_back(std::uint32_t(i));
    }
    grouped_ = true;
}

// A group's stiffness: each link's 12 × 12 block, and every held node (or the first node
// of a group with none) pinned by a penalty a million times the stiffest diagonal.
std::unique_ptr<BondStressModel::Factor> BondStressModel::factor(std::uint32_t root) const {
    const std::vector<std::uint32_t>& members = members_[root];
    auto f = std::make_unique<Factor>();
    f->local.resize(members.size());
    std::map<std::uint32_t, int> row;  // node → its first row
    for (std::size_t k = 0; k < members.size(); ++k) row[members[k]] = f->local[k] = int(6 * k);
    std::vector<Eigen::Triplet<double>> triplets;
    std::vector<double> diagonal(6 * members.size(), 0.0);
    for (std::uint32_t node : members)
        for (std::uint32_t i : nodeLinks_[node]) {
            if (broken_[i]) continue;
            const StressLink& l = links_[i];
            const auto [jt, jr] = jacobians(l, nodes_);
            const Stiffness k = stiffnessOf(l);
            const Link12 block = k.translation * jt.transpose() * jt + k.rotation * jr.transpose() * jr;
            const int base[2] = {row.at(l.a), row.at(l.b)};
            for (int r = 0; r < 12; ++r)
                for (int c = 0; c < 12; ++c)
                    if (block(r, c) != 0.0) triplets.emplace_back(base[r / 6] + r % 6, base[c / 6] + c % 6, block(r, c));
            for (int r = 0; r < 12; ++r) diagonal[std::size_t(base[r / 6] + r % 6)] += block(r, r);
        }
    const double penalty = 1e6 * std::max(1e-12, *std::max_element(diagonal.begin(), diagonal.end()));
    const bool held = std::any_of(members.begin(), members.end(), [&](std::uint32_t i) { return nodes_[i].held; });
    for (std::size_t k = 0; k < members.size(); ++k)
        if (nodes_[members[k]].held || (!held && k == 0))
            for (int d = 0; d < 6; ++d) triplets.emplace_back(int(6 * k) + d, int(6 * k) + d, penalty);
    Eigen::SparseMatrix<double> stiffness(int(6 * members.size()), int(6 * members.size()));
    stiffness.setFromTriplets(triplets.begin(), triplets.end());
    f->ldlt.compute(stiffness);
    if (f->ldlt.info() != Eigen::Success) throw std::runtime_error("bond stress model: the stiffness could not be factored");
    return f;
}

// The rigid motion a free group's loads give it: the acceleration a of its centre of mass c
// and α = I⁻¹·T, T the loads' torque about c and I the group's inertia there. Taking each
// node's inertial force m·(a + α × r) and torque I_node·α (r = x − c) out of its loads leaves
// no force and no torque on the group (the rotation's centripetal part is left out: the
// model's displacements are small).
BondStressModel::RigidMotion BondStressModel::motion(std::uint32_t root, const NodeLoads& loads) const {
    const std::vector<std::uint32_t>& members = members_[root];
    RigidMotion m;
    double mass = 0.0;
    glm::dvec3 force(0.0);
    for (std::uint32_t i : members) mass += nodes_[i].mass, m.centre += nodes_[i].mass * nodes_[i].position, force += loads.force[i];
    if (!(mass > 0.0)) return {};
    m.centre /= mass;
    glm::dvec3 torque(0.0);
    glm::dmat3 inertia(0.0);
    for (std::uint32_t i : members) {
        const glm::dvec3 r = nodes_[i].position - m.centre;
        torque += loads.torque[i] + glm::cross(r, loads.force[i]);
        inertia += nodes_[i].inertia + nodes_[i].mass * (glm::dot(r, r) * glm::dmat3(1.0) - glm::outerProduct(r, r));
    }
    // Point masses in a line have no inertia about it: a billionth of the trace keeps I
    // invertible, and a torque about that line stays with the node that holds the group.
    const double trace = inertia[0][0] + inertia[1][1] + inertia[2][2];
    m.linear = force / mass;
    m.angular = glm::inverse(inertia + 1e-9 * std::max(trace, 1e-30) * glm::dmat3(1.0)) * torque;
    return m;
}

// One group's links' stresses into `out`. A group with no held node falls or flies as a
// whole: its own inertia balances its loads.
void BondStressModel::solve(std::uint32_t root, const NodeLoads& loads, std::vector<double>& out) {
    const std::vector<std::uint32_t>& members = members_[root];
    std::unique_ptr<Factor>& f = factors_[root];
    if (!f) f = factor(root);
    const bool held = std::any_of(members.begin(), members.end(), [&](std::uint32_t i) { return nodes_[i].held; });
    const RigidMotion m = held ? RigidMotion{} : motion(root, loads);
    Vector rhs(Eigen::Index(6 * members.size()));
    for (std::size_t k = 0; k < members.size(); ++k) {
        const StressNode& node = nodes_[members[k]];
        const glm::dvec3 force = loads.force[members[k]] - node.mass * (m.linear + glm::cross(m.angular, node.position - m.centre));
        const glm::dvec3 torque = loads.torque[members[k]] - node.inertia * m.angular;
        for (int d = 0; d < 3; ++d)
            rhs[Eigen::Index(6 * k + d)] = force[d], rhs[Eigen::Index(6 * k + 3 + d)] = torque[d];
    }
    const Vector u = f->ldlt.solve(rhs);
    std::map<std::uint32_t, Eigen::Index> row;
    for (std::size_t k = 0; k < members.size(); ++k) row[members[k]] = Eigen::Index(6 * k);
    for (std::uint32_t node : members)
        for (std::uint32_t i : nodeLinks_[node]) {
            if (broken_[i]) continue;
            const StressLink& l = links_[i];
            const auto [jt, jr] = jacobians(l, nodes_);
            Eigen::Matrix<double, 12, 1> ul;
            ul << u.segment<6>(row.at(l.a)), u.segment<6>(row.at(l.b));
            const Stiffness k = stiffnessOf(l);
            const Eigen::Vector3d opening = -k.translation * (jt * ul), twist = -k.rotation * (jr * ul);
            out[i] = principalStress(l, {opening.x(), opening.y(), opening.z()}, {twist.x(), twist.y(), twist.z()});
        }
}

std::vector<double> BondStressModel::stresses(const NodeLoads& loads, const std::vector<bool>* active) {
    if (!grouped_) group();
    std::vector<double> out(links_.size(), 0.0);
    std::vector<bool> solved(nodes_.size(), false);
    for (std::size_t i = 0; i < nodes_.size(); ++i) {
        const std::uint32_t root = group_[i];
        if (solved[root] || (active && !(*active)[i]) || members_[root].size() < 2) continue;
        solved[root] = true;
        solve(root, loads, out);
    }
    return out;
}

}  // namespace dawnforge::sim
