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

// The bond's stiffness: translation ∝ A, rotation ∝ A·r²/4 (E/L = 1: only the ratios matter,
// the forces a load makes do not depend on the scale).
struct Stiffness {
    double translation, rotation;
};
Stiffness stiffnessOf(const StressLink& l) {
    const double r = radiusOf(l.area);
    return {l.area, l.area * r * r / 4.0};
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
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt;
};

BondStressModel::BondStressModel(std::vector<StressNode> nodes, std::vector<StressLink> links)
    : nodes_(std::move(nodes)), links_(std::move(links)), broken_(links_.size(), false) {
    for (const StressLink& l : links_)
        if (l.a >= nodes_.size() || l.b >= nodes_.size() || l.a == l.b || !(l.area > 0.0))
            throw InputError("bond stress model: a bond joins missing pieces, a piece to itself, or has no area");
}

BondStressModel::~BondStressModel() = default;

void BondStressModel::breakLink(std::size_t link) {
    if (!broken_[link]) broken_[link] = true, factor_.reset();
}

// Groups (union-find over the unbroken links, smallest index first), then the stiffness:
// each link's 12 × 12 block, and every held node, and the first node of every group with
// none, pinned by a penalty a million times the stiffest diagonal.
void BondStressModel::factor() {
    const std::size_t n = nodes_.size();
    UnionFind groups(n);
    for (std::size_t i = 0; i < links_.size(); ++i)
        if (!broken_[i]) groups.unite(links_[i].a, links_[i].b);
    group_.resize(n);
    for (std::size_t i = 0; i < n; ++i) group_[i] = groups.find(std::uint32_t(i));
    groupHeld_.assign(n, false);
    for (std::size_t i = 0; i < n; ++i)
        if (nodes_[i].held) groupHeld_[group_[i]] = true;

    std::vector<Eigen::Triplet<double>> triplets;
    std::vector<double> diagonal(6 * n, 0.0);
    for (std::size_t i = 0; i < links_.size(); ++i) {
        if (broken_[i]) continue;
        const StressLink& l = links_[i];
        const auto [jt, jr] = jacobians(l, nodes_);
        const Stiffness k = stiffnessOf(l);
        const Link12 block = k.translation * jt.transpose() * jt + k.rotation * jr.transpose() * jr;
        const std::size_t base[2] = {6 * std::size_t(l.a), 6 * std::size_t(l.b)};
        for (int r = 0; r < 12; ++r)
            for (int c = 0; c < 12; ++c)
                if (block(r, c) != 0.0) triplets.emplace_back(int(base[r / 6] + r % 6), int(base[c / 6] + c % 6), block(r, c));
        for (int r = 0; r < 12; ++r) diagonal[base[r / 6] + r % 6] += block(r, r);
    }
    const double penalty = 1e6 * std::max(1e-12, *std::max_element(diagonal.begin(), diagonal.end()));
    for (std::size_t i = 0; i < n; ++i)
        if (nodes_[i].held || (!groupHeld_[group_[i]] && group_[i] == i))
            for (int k = 0; k < 6; ++k) triplets.emplace_back(int(6 * i + k), int(6 * i + k), penalty);
    Eigen::SparseMatrix<double> stiffness(int(6 * n), int(6 * n));
    stiffness.setFromTriplets(triplets.begin(), triplets.end());
    factor_ = std::make_unique<Factor>();
    factor_->ldlt.compute(stiffness);
    if (factor_->ldlt.info() != Eigen::Success) throw std::runtime_error("bond stress model: the stiffness could not be factored");
}

std::vector<double> BondStressModel::stresses(const NodeLoads& loads) {
    if (!factor_) factor();
    const std::size_t n = nodes_.size();
    // Groups with no held node fall or fly as a whole: their own inertia balances the mean load.
    std::vector<glm::dvec3> groupForce(n, glm::dvec3(0.0));
    std::vector<double> groupMass(n, 0.0);
    for (std::size_t i = 0; i < n; ++i)
        if (!groupHeld_[group_[i]]) groupForce[group_[i]] += loads.force[i], groupMass[group_[i]] += nodes_[i].mass;
    Vector rhs(6 * n);
    for (std::size_t i = 0; i < n; ++i) {
        glm::dvec3 f = loads.force[i];
        const std::uint32_t g = group_[i];
        if (!groupHeld_[g] && groupMass[g] > 0.0) f -= nodes_[i].mass * groupForce[g] / groupMass[g];
        for (int k = 0; k < 3; ++k) rhs[Eigen::Index(6 * i + k)] = f[k], rhs[Eigen::Index(6 * i + 3 + k)] = loads.torque[i][k];
    }
    const Vector u = factor_->ldlt.solve(rhs);
    std::vector<double> out(links_.size(), 0.0);
    for (std::size_t i = 0; i < links_.size(); ++i) {
        if (broken_[i]) continue;
        const StressLink& l = links_[i];
        const auto [jt, jr] = jacobians(l, nodes_);
        Eigen::Matrix<double, 12, 1> ul;
        ul << u.segment<6>(Eigen::Index(6 * l.a)), u.segment<6>(Eigen::Index(6 * l.b));
        const Stiffness k = stiffnessOf(l);
        const Eigen::Vector3d opening = -k.translation * (jt * ul), twist = -k.rotation * (jr * ul);
        out[i] = principalStress(l, {opening.x(), opening.y(), opening.z()}, {twist.x(), twist.y(), twist.z()});
    }
    return out;
}

}  // namespace dawnforge::sim
