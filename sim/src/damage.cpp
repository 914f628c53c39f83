// Contact damage on the bond graph (damage.hpp says the rules).
#include "damage.hpp"

#include <algorithm>
#include <cmath>

namespace dawnforge::sim {

DamageModel::DamageModel(std::size_t nodes, std::uint32_t ground, std::vector<DamageLink> links, DamageRules rules)
    : nodes_(nodes), ground_(ground), links_(std::move(links)), rules_(rules), nodeLinks_(nodes),
      broken_(links_.size(), false), damage_(links_.size(), 0.0), struck_(nodes, 0.0) {
    for (std::size_t i = 0; i < links_.size(); ++i) {
        nodeLinks_[links_[i].a].push_back(std::uint32_t(i));
        nodeLinks_[links_[i].b].push_back(std::uint32_t(i));
    }
}

void DamageModel::strike(std::uint32_t node, double impulse) {
    if (node != ground_ && impulse > 0.0) struck_[node] += impulse;
}

// The blows go out hop by hop: every node reached at hop k (the struck ones at 0) splits what
// it holds over its unbroken links by area, and sends their shares through those that lead to
// nodes not reached before hop k (a share that would go back towards the blow is not counted:
// a sliver that is a piece's only way on takes its share, not the whole blow); a node not
// reached before holds `transmission` of it at hop k + 1, and one reached at hop k (struck
// beside it) only takes the damage. Nodes and links are visited in ascending order, so the
// sums are the same on every run.
std::vector<std::size_t> DamageModel::spread(double dt) {
    const double age = std::exp2(-dt / rules_.halfLife);
    for (double& d : damage_) d *= age;
    std::vector<int> reached(nodes_, -1);  // the hop at which a node was reached
    std::vector<double> held(nodes_, 0.0);
    std::vector<std::uint32_t> front;
    for (std::uint32_t p = 0; p < nodes_; ++p) {
        if (!(struck_[p] > 0.0)) continue;
        double carried = 0.0;  // what its links hold over the step
        for (std::uint32_t l : nodeLinks_[p])
            if (!broken_[l]) carried += links_[l].force * dt;
        if (struck_[p] > carried) front.push_back(p), reached[p] = 0, held[p] = struck_[p] - carried;
    }
    for (int hop = 0; hop < rules_.hops && !front.empty(); ++hop) {
        std::vector<std::uint32_t> next;
        for (std::uint32_t p : front) {
            const auto other = [&](std::uint32_t l) { return links_[l].a == p ? links_[l].b : links_[l].a; };
            // Every unbroken link but those back to nodes reached before: a node reached at the same
            // hop (two pieces struck side by side) takes its share but does not pass it on again.
            const auto onward = [&](std::uint32_t l) {
                return !broken_[l] && (reached[other(l)] < 0 || reached[other(l)] >= hop);
            };
            double area = 0.0;  // of all its unbroken links: what goes back to where it came from is spent there
            for (std::uint32_t l : nodeLinks_[p])
                if (!broken_[l]) area += links_[l].area;
            if (!(area > 0.0)) continue;
            for (std::uint32_t l : nodeLinks_[p]) {
                if (!onward(l)) continue;
                const double crossed = held[p] * links_[l].area / area;
                damage_[l] += crossed;
                const std::uint32_t q = other(l);
                if (q == ground_ || reached[q] == hop) continue;
                if (reached[q] < 0) reached[q] = hop + 1, next.push_back(q);
                held[q] += rules_.transmission * crossed;
            }
        }
        std::sort(next.begin(), next.end());
        front = std::move(next);
    }
    std::fill(struck_.begin(), struck_.end(), 0.0);
    std::vector<std::size_t> over;
    for (std::size_t i = 0; i < links_.size(); ++i)
        if (!broken_[i] && damage_[i] > links_[i].force * rules_.impactTime) over.push_back(i);
    return over;
}

}  // namespace dawnforge::sim
