// The leaf picture (leaves.hpp): ellipses of leaves in a disc, drawn in a fixed order.
#include <dawnforge/core/leaves.hpp>

#include <dawnforge/core/seed.hpp>

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>

namespace dawnforge {

namespace {

struct Leaf {
    glm::dvec2 centre, axis;  // axis: unit, along the leaf
    double length, width;     // half-axes
    glm::dvec3 colour;        // linear
};

constexpr int kLeaves = 96;
constexpr int kSamples = 4;  // per texel and axis
constexpr int kCells = 16;   // per axis: each cell lists the leaves that may cover it

// The leaves whose bounding square (centre ± length, which holds the ellipse) meets each cell,
// in drawing order.
using LeafCells = std::vector<std::vector<int>>;
LeafCells leafCells(const std::vector<Leaf>& all) {
    LeafCells cells(std::size_t(kCells) * kCells);
    const auto cellOf = [](double v) { return std::clamp(int(std::floor(v * kCells)), 0, kCells - 1); };
    for (int k = 0; k < int(all.size()); ++k) {
        const Leaf& l = all[std::size_t(k)];
        for (int y = cellOf(l.centre.y - l.length); y <= cellOf(l.centre.y + l.length); ++y)
            for (int x = cellOf(l.centre.x - l.length); x <= cellOf(l.centre.x + l.length); ++x)
                cells[std::size_t(y) * kCells + std::size_t(x)].push_back(k);
    }
    return cells;
}

double srgbToLinear(double s) { return s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4); }
std::uint8_t linearToSrgb8(double l) {
    const double s = l <= 0.0031308 ? l * 12.92 : 1.055 * std::pow(l, 1.0 / 2.4) - 0.055;
    return std::uint8_t(std::lround(std::clamp(s, 0.0, 1.0) * 255.0));
}

// Leaves in a disc of radius 0.42 about the card's middle, none reaching its edge.
std::vector<Leaf> leaves() {
    Rng rng(deriveSeed(0x6c656166ull, "leaf picture"));
    std::vector<Leaf> out;
    while (int(out.size()) < kLeaves) {
        const glm::dvec2 c(rng.uniform(0.08, 0.92), rng.uniform(0.08, 0.92));
        if (glm::length(c - 0.5) > 0.38) continue;
        const double angle = rng.uniform(0.0, 6.283185307179586);
        Leaf l;
        l.centre = c;
        l.axis = {std::cos(angle), std::sin(angle)};
        l.length = rng.uniform(0.06, 0.085);
        l.width = l.length * rng.uniform(0.38, 0.5);
        const double shade = rng.uniform(0.75, 1.15);
        l.colour = glm::dvec3(srgbToLinear(0.22), srgbToLinear(0.42), srgbToLinear(0.13)) * shade * shade;
        out.push_back(l);
    }
    return out;
}

// The last leaf over p (the one drawn on top), with a darker midrib; none: alpha 0. Only the
// leaves of p's cell can cover it.
bool leafAt(const std::vector<Leaf>& all, const LeafCells& cells, glm::dvec2 p, glm::dvec3& colour) {
    const std::vector<int>& near = cells[std::size_t(std::min(int(p.y * kCells), kCells - 1)) * kCells +
                                         std::size_t(std::min(int(p.x * kCells), kCells - 1))];
    for (auto k = near.rbegin(); k != near.rend(); ++k) {
        const Leaf& l = all[std::size_t(*k)];
        const glm::dvec2 d = p - l.centre;
        const double along = glm::dot(d, l.axis) / l.length, across = (d.x * -l.axis.y + d.y * l.axis.x) / l.width;
        if (along * along + across * across > 1.0) continue;
        colour = l.colour * (std::abs(across) < 0.08 ? 0.7 : 1.0 + 0.15 * along);
        return true;
    }
    return false;
}

// Level 0 in linear light (rgb) and coverage (a), the uncovered texels' colour still unset.
std::vector<glm::dvec4> levelZero(const std::vector<Leaf>& all) {
    const LeafCells cells = leafCells(all);
    std::vector<glm::dvec4> texels(std::size_t(kLeafSize) * kLeafSize, glm::dvec4(0.0));
    for (int y = 0; y < kLeafSize; ++y)
        for (int x = 0; x < kLeafSize; ++x) {
            glm::dvec4& t = texels[std::size_t(y) * kLeafSize + std::size_t(x)];
            for (int j = 0; j < kSamples; ++j)
                for (int i = 0; i < kSamples; ++i) {
                    glm::dvec3 c;
                    const glm::dvec2 p((x + (i + 0.5) / kSamples) / kLeafSize, (y + (j + 0.5) / kSamples) / kLeafSize);
                    if (leafAt(all, cells, p, c)) t += glm::dvec4(c, 1.0);
                }
            if (t.a > 0.0) t = glm::dvec4(glm::dvec3(t) / t.a, t.a / (kSamples * kSamples));
        }
    return texels;
}

// The covered texels' mean colour on every uncovered one.
void fillUncovered(std::vector<glm::dvec4>& texels) {
    glm::dvec3 sum(0.0);
    double n = 0.0;
    for (const glm::dvec4& t : texels)
        if (t.a > 0.0) sum += glm::dvec3(t) * t.a, n += t.a;
    for (glm::dvec4& t : texels)
        if (t.a == 0.0) t = glm::dvec4(sum / n, 0.0);
}

double passing(const std::vector<glm::dvec4>& texels, double scale) {
    std::size_t pass = 0;
    for (const glm::dvec4& t : texels) pass += t.a * scale >= kLeafCutoff;
    return double(pass) / double(texels.size());
}

// The alpha scale at which `texels` pass the cutoff in the share `target` (bisection).
double coverageScale(const std::vector<glm::dvec4>& texels, double target) {
    double lo = 0.25, hi = 8.0;
    for (int k = 0; k < 40; ++k) {
        const double mid = 0.5 * (lo + hi);
        (passing(texels, mid) < target ? lo : hi) = mid;
    }
    return hi;
}

std::vector<glm::dvec4> halved(const std::vector<glm::dvec4>& above, int size) {
    std::vector<glm::dvec4> out(std::size_t(size) * std::size_t(size));
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const auto at = [&](int i, int j) { return above[std::size_t(2 * y + j) * std::size_t(2 * size) + std::size_t(2 * x + i)]; };
            out[std::size_t(y) * std::size_t(size) + std::size_t(x)] = 0.25 * (at(0, 0) + at(1, 0) + at(0, 1) + at(1, 1));
        }
    return out;
}

std::vector<std::uint8_t> encode(const std::vector<glm::dvec4>& texels, double alphaScale) {
    std::vector<std::uint8_t> out(texels.size() * 4);
    for (std::size_t k = 0; k < texels.size(); ++k) {
        for (int c = 0; c < 3; ++c) out[4 * k + std::size_t(c)] = linearToSrgb8(texels[k][c]);
        out[4 * k + 3] = std::uint8_t(std::lround(std::clamp(texels[k].a * alphaScale, 0.0, 1.0) * 255.0));
    }
    return out;
}

}  // namespace

LeafImage makeLeafImage() {
    std::vector<glm::dvec4> level = levelZero(leaves());
    fillUncovered(level);
    const double coverage = passing(level, 1.0);
    LeafImage image;
    image.rgba[0] = encode(level, 1.0);
    for (int l = 1; l < kLeafLevels; ++l) {
        level = halved(level, kLeafSize >> l);
        image.rgba[std::size_t(l)] = encode(level, coverageScale(level, coverage));
    }
    return image;
}

double leafCoverage(const LeafImage& image, int level) {
    const std::vector<std::uint8_t>& t = image.rgba[std::size_t(level)];
    std::size_t pass = 0;
    for (std::size_t k = 3; k < t.size(); k += 4) pass += t[k] >= 128;  // 128 / 255 ≥ kLeafCutoff
    return double(pass) / double(t.size() / 4);
}

}  // namespace dawnforge
