// The city plan (plan.hpp): a street grid bent by value noise, a coast with a promenade,
// blocks as the faces of the street graph (arrangement.cpp), and lots split from each block
// the way CityEngine does it (Parish and Mueller, "Procedural Modeling of Cities",
// SIGGRAPH 2001; Vanegas et al., "Procedural Generation of Parcels in Urban Modeling",
// Eurographics 2012): cut across the longest street frontage while it is too wide, then
// parallel to it while the lot is too deep, keeping every piece on a street.
#include <dawnforge/procgen/plan.hpp>

#include "arrangement.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/seed.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <span>
#include <unordered_map>
#include <utility>

namespace dawnforge::procgen {

namespace {

constexpr double kCoastStep = 20.0;         // metres between coastline samples (coastal lots are cut at them)
constexpr double kMaxBend = 0.2;            // node jitter limit, a fraction of the minor spacing (blocks stay convex)
constexpr double kRingSnap = 0.3;           // grid nodes this close to the city edge (x minor spacing) join the ring
constexpr double kSplitJitter = 0.1;        // a lot is cut at its middle +- this fraction
constexpr double kCutSnap = 0.5;            // metres: a cut passing this close to a vertex goes through it
constexpr double kOnLine = 1e-7;            // metres: a vertex this close to a cut line lies on it
constexpr double kCollinear = 1e-9;         // metres: a vertex this close to its neighbours' chord is dropped
constexpr double kMaxGridNodes = 4.0e6;     // a larger grid means a size that makes no sense for its spacing

void reportProgress(const ProgressFn& progress, double fraction) {
    if (!progress(fraction)) throw Cancelled();
}

double fade(double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }

// A lattice value in [-1, 1]: one fresh generator per lattice point.
double latticeValue(std::uint64_t seed, std::int64_t ix, std::int64_t iy) {
    const std::uint64_t key = (static_cast<std::uint64_t>(static_cast<std::uint32_t>(ix)) << 32) |
                              static_cast<std::uint32_t>(iy);
    return Rng(deriveSeed(seed, "lattice", key)).uniform(-1.0, 1.0);
}

// Smooth value noise in [-1, 1] with unit wavelength: it depends on p and the seed only.
double valueNoise(std::uint64_t seed, glm::dvec2 p) {
    const double fx = std::floor(p.x), fy = std::floor(p.y);
    const auto ix = static_cast<std::int64_t>(fx), iy = static_cast<std::int64_t>(fy);
    const double tx = fade(p.x - fx), ty = fade(p.y - fy);
    const double v00 = latticeValue(seed, ix, iy), v10 = latticeValue(seed, ix + 1, iy);
    const double v01 = latticeValue(seed, ix, iy + 1), v11 = latticeValue(seed, ix + 1, iy + 1);
    const double a = v00 + (v10 - v00) * tx, b = v01 + (v11 - v01) * tx;
    return a + (b - a) * ty;
}

// The y of a line running west to east (x ascending) at x: linear between its points, level
// beyond its ends, -infinity when it is empty (the coast and the promenade without a sea).
double yAt(std::span<const glm::dvec2> line, double x) {
    if (line.empty()) return -std::numeric_limits<double>::infinity();
    if (x <= line.front().x) return line.front().y;
    if (x >= line.back().x) return line.back().y;
    const auto it = std::upper_bound(line.begin(), line.end(), x, [](double v, glm::dvec2 p) { return v < p.x; });
    const glm::dvec2 b = *it, a = *(it - 1);
    return a.y + (b.y - a.y) * ((x - a.x) / (b.x - a.x));
}

// ---------------------------------------------------------------------------------------
// The land: the city rectangle north of the promenade's centre line.

struct Land {
    glm::dvec2 size{0.0};
    std::vector<glm::dvec2> promenade;  // centre line, west to east; empty without a sea

    double promenadeY(double x) const { return yAt(promenade, x); }
    bool contains(glm::dvec2 p) const {
        return p.x > 0.0 && p.x < size.x && p.y > 0.0 && p.y < size.y && p.y > promenadeY(p.x);
    }

    // The parameter intervals of a -> b that lie on the land, in order.
    std::vector<std::pair<double, double>> intervals(glm::dvec2 a, glm::dvec2 b) const {
        double t0 = 0.0, t1 = 1.0;
        const glm::dvec2 d = b - a;
        const auto clip = [&](double p, double q) {  // keep p * t <= q
            if (p == 0.0) return q >= 0.0;
            const double r = q / p;
            if (p < 0.0) t0 = std::max(t0, r);
            else t1 = std::min(t1, r);
            return t0 < t1;
        };
        if (!clip(-d.x, a.x) || !clip(d.x, size.x - a.x) || !clip(-d.y, a.y) || !clip(d.y, size.y - a.y))
            return {};
        std::vector<double> cuts{t0};
        for (std::size_t i = 0; i + 1 < promenade.size(); ++i) {
            const glm::dvec2 p = promenade[i], e = promenade[i + 1] - p;
            const double den = cross(d, e);
            if (den == 0.0) continue;
            const double t = cross(p - a, e) / den, s = cross(p - a, d) / den;
            if (s >= 0.0 && s <= 1.0 && t > t0 && t < t1) cuts.push_back(t);
        }
        cuts.push_back(t1);
        std::sort(cuts.begin(), cuts.end());
        std::vector<std::pair<double, double>> out;
        for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
            if (!(cuts[i + 1] > cuts[i])) continue;
            const glm::dvec2 mid = a + d * (0.5 * (cuts[i] + cuts[i + 1]));
            if (!promenade.empty() && !(mid.y > promenadeY(mid.x))) continue;
            if (!out.empty() && out.back().second == cuts[i]) out.back().second = cuts[i + 1];
            else out.emplace_back(cuts[i], cuts[i + 1]);
        }
        return out;
    }
};

// ---------------------------------------------------------------------------------------
// Streets

struct StreetGraph {
    std::vector<Street> streets;
    std::vector<ArrangementSegment> segments;  // weight: half the street's width
};

// Appends the land parts of a chain of segments as streets; a segment not `present` ends a piece.
void addClippedStreets(const Land& land, const std::vector<std::pair<glm::dvec2, glm::dvec2>>& chain,
                       const std::vector<bool>& present, bool major, double width,
                       std::vector<Street>& streets) {
    std::vector<glm::dvec2> current;
    const auto flush = [&] {
        if (current.size() >= 2) {
            Street street;
            street.id = static_cast<int>(streets.size());
            street.major = major;
            street.width = width;
            street.polyline = std::move(current);
            streets.push_back(std::move(street));
        }
        current.clear();
    };
    for (std::size_t k = 0; k < chain.size(); ++k) {
        if (!present[k]) {
            flush();
            continue;
        }
        // Plain variables, not a structured binding: lambdas may not capture those before clang 16.
        const glm::dvec2 a = chain[k].first, b = chain[k].second;
        const auto at = [&](double t) { return t == 0.0 ? a : t == 1.0 ? b : a + (b - a) * t; };
        for (const auto& [ta, tb] : land.intervals(a, b)) {
            const glm::dvec2 pa = at(ta);
            if (!(ta == 0.0 && !current.empty() && current.back() == pa)) {
                flush();
                current.push_back(pa);
            }
            current.push_back(at(tb));
        }
        if (!current.empty() && current.back() != b) flush();
    }
    flush();
}

// The street grid: lines every minorSpacing through the city's centre, rotated by `angle`,
// with their nodes bent by value noise; nodes near the city's edge snap onto the ring road.
struct StreetGrid {
    int n = 0;  // lines -n..n in each direction
    std::vector<glm::dvec2> nodes;
    std::vector<unsigned> ringSides;  // per node, bit k: snapped onto side k of the ring
    std::size_t index(int i, int j) const {
        return static_cast<std::size_t>(j + n) * (2 * n + 1) + static_cast<std::size_t>(i + n);
    }
};

StreetGrid streetGrid(const StreetRecipe& r, const Land& land, std::uint64_t seed) {
    const glm::dvec2 size = land.size;
    const bool sea = !land.promenade.empty();
    const double s = r.minorSpacing;
    const double theta = r.angle * std::numbers::pi / 180.0;
    const glm::dvec2 u{std::cos(theta), std::sin(theta)}, v{-u.y, u.x};
    const glm::dvec2 centre = 0.5 * size;
    StreetGrid grid;
    grid.n = static_cast<int>(std::ceil(0.5 * glm::length(size) / s)) + 1;
    const int n = grid.n;
    const std::uint64_t bendX = deriveSeed(seed, "street-bend", 0), bendY = deriveSeed(seed, "street-bend", 1);
    const double maxBend = std::min(r.bend, kMaxBend * s);
    grid.nodes.resize(static_cast<std::size_t>(2 * n + 1) * (2 * n + 1));
    grid.ringSides.resize(grid.nodes.size(), 0u);
    const double snap = kRingSnap * s;
    for (int j = -n; j <= n; ++j)
        for (int i = -n; i <= n; ++i) {
            glm::dvec2 p = centre + (i * s) * u + (j * s) * v;
            if (maxBend > 0.0) {
                const glm::dvec2 q = p / r.bendWavelength;
                glm::dvec2 offset = r.bend * glm::dvec2(valueNoise(bendX, q), valueNoise(bendY, q));
                const double length = glm::length(offset);
                if (length > maxBend) offset *= maxBend / length;
                p += offset;
            }
            unsigned sides = 0;
            if (std::abs(p.x) < snap) p.x = 0.0, sides |= 1u;
            else if (std::abs(p.x - size.x) < snap) p.x = size.x, sides |= 2u;
            if (!sea && std::abs(p.y) < snap) p.y = 0.0, sides |= 4u;
            else if (std::abs(p.y - size.y) < snap) p.y = size.y, sides |= 8u;
            grid.nodes[grid.index(i, j)] = p;
            grid.ringSides[grid.index(i, j)] = sides;
        }
    return grid;
}

// The promenade (a major street whose seaward kerb is the coastline) and the ring road.
void addPromenadeAndRing(const StreetRecipe& r, double promenadeWidth, const Land& land, StreetGraph& graph) {
    const glm::dvec2 size = land.size;
    const bool sea = !land.promenade.empty();
    if (sea) {
        Street promenade;
        promenade.id = 0;
        promenade.major = true;
        promenade.width = promenadeWidth;
        promenade.polyline = land.promenade;
        graph.streets.push_back(std::move(promenade));
        for (std::size_t k = 0; k + 1 < land.promenade.size(); ++k)
            graph.segments.push_back({land.promenade[k], land.promenade[k + 1], 0.5 * promenadeWidth});
    }
    Street ring;
    ring.id = static_cast<int>(graph.streets.size());
    ring.width = r.minorWidth;
    if (sea)
        ring.polyline = {{0.0, land.promenade.front().y}, {0.0, size.y}, size, {size.x, land.promenade.back().y}};
    else
        ring.polyline = {{0.0, 0.0}, {size.x, 0.0}, size, {0.0, size.y}, {0.0, 0.0}};
    graph.streets.push_back(std::move(ring));
    const glm::dvec2 corners[4] = {{0.0, 0.0}, {size.x, 0.0}, size, {0.0, size.y}};
    for (int k = 0; k < 4; ++k) graph.segments.push_back({corners[k], corners[(k + 1) % 4], 0.5 * r.minorWidth});
}

// The grid's lines as streets clipped to the land, and their segments. Where both ends of a
// segment snapped onto one side of the ring, the ring road is the street there.
void addGridStreets(const StreetRecipe& r, const Land& land, const StreetGrid& grid, StreetGraph& graph) {
    const int n = grid.n;
    const double s = r.minorSpacing;
    const auto isMajor = [&](int i) {
        const double k = std::round(i * s / r.majorSpacing);
        return std::round(k * r.majorSpacing / s) == i;
    };
    const auto touchesCity = [&](glm::dvec2 a, glm::dvec2 b) {
        return std::max(a.x, b.x) >= 0.0 && std::min(a.x, b.x) <= land.size.x && std::max(a.y, b.y) >= 0.0 &&
               std::min(a.y, b.y) <= land.size.y;
    };
    for (int direction = 0; direction < 2; ++direction)
        for (int line = -n; line <= n; ++line) {
            const bool major = isMajor(line);
            const double width = major ? r.majorWidth : r.minorWidth;
            std::vector<std::pair<glm::dvec2, glm::dvec2>> chain;
            std::vector<bool> present;
            for (int k = -n; k < n; ++k) {
                // direction 0: the line u = line * s, running along v; 1: v = line * s, along u.
                const std::size_t ia = direction == 0 ? grid.index(line, k) : grid.index(k, line);
                const std::size_t ib = direction == 0 ? grid.index(line, k + 1) : grid.index(k + 1, line);
                const glm::dvec2 a = grid.nodes[ia], b = grid.nodes[ib];
                const bool keep = (grid.ringSides[ia] & grid.ringSides[ib]) == 0 && touchesCity(a, b);
                chain.emplace_back(a, b);
                present.push_back(keep);
                if (keep) graph.segments.push_back({a, b, 0.5 * width});
            }
            addClippedStreets(land, chain, present, major, width, graph.streets);
        }
}

// The promenade first, then the ring road, then the grid's lines.
StreetGraph buildStreets(const StreetRecipe& r, double promenadeWidth, const Land& land, std::uint64_t seed) {
    StreetGraph graph;
    addPromenadeAndRing(r, promenadeWidth, land, graph);
    addGridStreets(r, land, streetGrid(r, land, seed), graph);
    return graph;
}

// ---------------------------------------------------------------------------------------
// Blocks

// Drops vertices that lie on their neighbours' chord; an edge made of two keeps the larger
// weight.
void dropCollinear(Polygon2& polygon, std::vector<double>& weight) {
    bool changed = true;
    while (changed && polygon.size() > 3) {
        changed = false;
        for (std::size_t i = 0; i < polygon.size() && polygon.size() > 3; ++i) {
            const std::size_t m = polygon.size(), prev = (i + m - 1) % m, next = (i + 1) % m;
            if (distanceToSegment(polygon[i], polygon[prev], polygon[next]) >= kCollinear) continue;
            weight[prev] = std::max(weight[prev], weight[i]);
            polygon.erase(polygon.begin() + static_cast<std::ptrdiff_t>(i));
            weight.erase(weight.begin() + static_cast<std::ptrdiff_t>(i));
            changed = true;
            --i;
        }
    }
}

// Whether `curb` is a simple counter-clockwise polygon inside `face` that keeps at least
// offset[j] from every face edge j.
bool validCurb(const Polygon2& curb, const Polygon2& face, const std::vector<double>& offset) {
    if (curb.size() < 3 || signedArea(curb) <= 0.0 || !isSimple(curb)) return false;
    for (glm::dvec2 p : curb)
        if (!containsPoint(face, p)) return false;
    const std::size_t n = face.size(), m = curb.size();
    for (std::size_t j = 0; j < n; ++j) {
        const glm::dvec2 a = face[j], b = face[(j + 1) % n];
        const double need = offset[j] - 1e-9;
        for (std::size_t k = 0; k < m; ++k) {
            const glm::dvec2 c = curb[k], d = curb[(k + 1) % m];
            if (distanceToSegment(c, a, b) < need || distanceToSegment(a, c, d) < need ||
                distanceToSegment(b, c, d) < need)
                return false;
        }
    }
    return true;
}

// The face moved inwards by offset[i] along each edge i (mitred); empty when that fails.
Polygon2 curbPolygon(const Polygon2& face, const std::vector<double>& offset) {
    const std::size_t n = face.size();
    std::vector<glm::dvec2> normal(n);  // inward (the face is counter-clockwise)
    for (std::size_t i = 0; i < n; ++i) normal[i] = inwardNormal(face[i], face[(i + 1) % n]);
    if (isConvex(face)) {
        // Intersection of the inward half-planes: exact for convex faces, and edges that
        // the offset swallows simply vanish.
        Polygon2 curb = face;
        for (std::size_t i = 0; i < n && !curb.empty(); ++i)
            curb = clipHalfPlane(curb, -normal[i], -(glm::dot(normal[i], face[i]) + offset[i]));
        curb = simplifyPolygon(curb, kCollinear);
        return validCurb(curb, face, offset) ? curb : Polygon2{};
    }
    // Mitred offset lines; an edge whose offset turns around is swallowed by its
    // neighbours (an edge event of the weighted straight skeleton), until none does.
    std::vector<std::size_t> live(n);
    for (std::size_t i = 0; i < n; ++i) live[i] = i;
    Polygon2 curb;
    while (live.size() >= 3) {
        const std::size_t m = live.size();
        curb.assign(m, glm::dvec2(0.0));
        bool failed = false;
        for (std::size_t k = 0; k < m && !failed; ++k) {
            const std::size_t e0 = live[(k + m - 1) % m], e1 = live[k];
            const glm::dvec2 n0 = normal[e0], n1 = normal[e1], ref = face[e1];
            const double r0 = offset[e0] - glm::dot(n0, ref - face[e0]), r1 = offset[e1];
            const double det = cross(n0, n1);
            if (std::abs(det) < 1e-6) {
                failed = std::abs(r0 - r1) > 1e-9 || glm::dot(n0, n1) < 0.0;
                curb[k] = ref + r0 * (n0 + n1) / (1.0 + glm::dot(n0, n1));
            } else {
                curb[k] = ref + glm::dvec2((r0 * n1.y - r1 * n0.y) / det, (n0.x * r1 - n1.x * r0) / det);
            }
        }
        if (failed) {
            curb.clear();
            break;
        }
        std::size_t turned = m;
        for (std::size_t k = 0; k < m && turned == m; ++k) {
            const std::size_t e = live[k];
            if (glm::dot(curb[(k + 1) % m] - curb[k], face[(e + 1) % n] - face[e]) <= 0.0) turned = k;
        }
        if (turned == m) break;
        live.erase(live.begin() + static_cast<std::ptrdiff_t>(turned));
        curb.clear();
    }
    if (validCurb(curb, face, offset)) return curb;
    // A uniform inset by the widest street keeps every street's clearance.
    const double widest = *std::max_element(offset.begin(), offset.end());
    curb = insetPolygon(face, widest);
    return validCurb(curb, face, offset) ? curb : Polygon2{};
}

// ---------------------------------------------------------------------------------------
// Lots

struct Piece {
    Polygon2 polygon;
    std::vector<bool> street;  // per edge: on the block's inner boundary
};

// The longest street edge: (index, length), index -1 when there is none.
std::pair<int, double> longestStreetEdge(const Piece& piece) {
    std::pair<int, double> best{-1, 0.0};
    const std::size_t n = piece.polygon.size();
    for (std::size_t i = 0; i < n; ++i) {
        if (!piece.street[i]) continue;
        const double length = glm::distance(piece.polygon[i], piece.polygon[(i + 1) % n]);
        if (length > best.second) best = {static_cast<int>(i), length};
    }
    return best;
}

// Drops vertices on their neighbours' chord (a merged edge is a street edge when both were).
void dropCollinear(Piece& piece) {
    Polygon2& p = piece.polygon;
    for (std::size_t i = 0; i < p.size() && p.size() > 3;) {
        const std::size_t m = p.size(), prev = (i + m - 1) % m, next = (i + 1) % m;
        if (glm::distance(p[i], p[next]) > kCollinear && distanceToSegment(p[i], p[prev], p[next]) >= kCollinear) {
            ++i;
            continue;
        }
        piece.street[prev] = piece.street[prev] && piece.street[i];
        p.erase(p.begin() + static_cast<std::ptrdiff_t>(i));
        piece.street.erase(piece.street.begin() + static_cast<std::ptrdiff_t>(i));
        i = 0;
    }
}

// Cuts a convex piece along dot(normal, x) = c: first the side where dot <= c. The cut's
// edges are not street edges.
std::pair<Piece, Piece> cutPiece(const Piece& piece, glm::dvec2 normal, double c, bool snap = true) {
    const Polygon2& p = piece.polygon;
    const std::size_t n = p.size();
    // A cut that passes close to a vertex goes through it: no sliver edges.
    for (glm::dvec2 q : p)
        if (snap && std::abs(glm::dot(normal, q) - c) < kCutSnap) {
            c = glm::dot(normal, q);
            break;
        }
    std::vector<double> dist(n);
    for (std::size_t i = 0; i < n; ++i) {
        dist[i] = glm::dot(normal, p[i]) - c;
        if (std::abs(dist[i]) < kOnLine) dist[i] = 0.0;
    }
    std::pair<Piece, Piece> halves;
    for (int side = 0; side < 2; ++side) {
        Piece& out = side == 0 ? halves.first : halves.second;
        const double sign = side == 0 ? 1.0 : -1.0;
        for (std::size_t i = 0; i < n; ++i) {
            const std::size_t next = (i + 1) % n;
            const double di = sign * dist[i], dn = sign * dist[next];
            const auto crossing = [&] { return p[i] + (p[next] - p[i]) * (dist[i] / (dist[i] - dist[next])); };
            if (di <= 0.0) {
                if (dn <= 0.0) {
                    out.polygon.push_back(p[i]);
                    out.street.push_back(piece.street[i]);
                } else if (di < 0.0) {
                    out.polygon.push_back(p[i]);
                    out.street.push_back(piece.street[i]);
                    out.polygon.push_back(crossing());
                    out.street.push_back(false);
                } else {
                    out.polygon.push_back(p[i]);
                    out.street.push_back(false);
                }
            } else if (dn < 0.0) {
                out.polygon.push_back(crossing());
                out.street.push_back(piece.street[i]);
            }
        }
        dropCollinear(out);
    }
    return halves;
}

struct LotSplitter {
    const LotRecipe& recipe;
    Rng rng;
    std::vector<Piece> lots;

    bool acceptable(const Piece& piece) const {
        return piece.polygon.size() >= 3 && signedArea(piece.polygon) >= recipe.minArea &&
               longestStreetEdge(piece).second >= recipe.minFrontage;
    }

    // Tries the cut at t = 0.5 + jitter, then at 0.5; true when it split the piece.
    bool trySplit(const Piece& piece, glm::dvec2 normal, double start, double extent, double jitter, int depth) {
        for (double t : {0.5 + jitter, 0.5}) {
            auto halves = cutPiece(piece, normal, start + t * extent);
            if (!acceptable(halves.first) || !acceptable(halves.second)) continue;
            split(std::move(halves.first), depth + 1);
            split(std::move(halves.second), depth + 1);
            return true;
        }
        return false;
    }

    void split(Piece piece, int depth) {
        const auto [edge, frontage] = longestStreetEdge(piece);
        if (edge < 0) return;
        const double jitter = rng.uniform(-kSplitJitter, kSplitJitter);
        const std::size_t n = piece.polygon.size();
        const glm::dvec2 a = piece.polygon[static_cast<std::size_t>(edge)];
        const glm::dvec2 along = (piece.polygon[(static_cast<std::size_t>(edge) + 1) % n] - a) / frontage;
        const glm::dvec2 inward{-along.y, along.x};
        if (depth < 64) {
            if (frontage > recipe.maxFrontage &&
                trySplit(piece, along, glm::dot(along, a), frontage, jitter, depth))
                return;
            double lotDepth = 0.0;
            for (glm::dvec2 p : piece.polygon) lotDepth = std::max(lotDepth, glm::dot(inward, p - a));
            if (lotDepth > recipe.maxDepth &&
                trySplit(piece, inward, glm::dot(inward, a), lotDepth, jitter, depth))
                return;
        }
        if (signedArea(piece.polygon) >= recipe.minArea) lots.push_back(std::move(piece));
    }
};

// The pieces of a simple counter-clockwise piece cut from its first reflex vertex `v` to
// boundary point `h` on edge `j` (h == polygon[j] or polygon[j + 1] when snapped there).
std::pair<Piece, Piece> cutAtReflex(const Piece& piece, std::size_t v, std::size_t j, glm::dvec2 h) {
    const Polygon2& p = piece.polygon;
    const std::size_t n = p.size(), jn = (j + 1) % n;
    std::pair<Piece, Piece> out;
    const auto push = [](Piece& piece, glm::dvec2 q, bool street) {
        piece.polygon.push_back(q);
        piece.street.push_back(street);
    };
    // First piece: v, v + 1, ..., j, then h (unless h is p[j]), then back to v along the cut.
    for (std::size_t i = v; i != j; i = (i + 1) % n) push(out.first, p[i], piece.street[i]);
    if (h == p[j]) {
        push(out.first, p[j], false);
    } else {
        push(out.first, p[j], piece.street[j]);
        push(out.first, h, false);
    }
    // Second piece: h (or p[j + 1]), ..., v, then back along the cut.
    if (h != p[jn]) push(out.second, h, piece.street[j]);
    for (std::size_t i = jn; i != v; i = (i + 1) % n) push(out.second, p[i], piece.street[i]);
    push(out.second, p[v], false);
    return out;
}

// Convex pieces of a simple counter-clockwise piece: each reflex vertex is cut along the
// bisector of its angle to the opposite boundary. Unlike a partition by diagonals (CGAL's
// Partition_2), the cuts end anywhere on the boundary, so a gently curved coastal block
// becomes strips across it instead of a fan of slivers.
void convexSplit(Piece piece, std::vector<Piece>& out, int depth) {
    const Polygon2& p = piece.polygon;
    const std::size_t n = p.size();
    if (n < 3) return;
    const std::size_t v = reflexVertex(p);
    if (v == n) {
        out.push_back(std::move(piece));
        return;
    }
    if (depth > 256) return;
    const glm::dvec2 b = p[v];
    const glm::dvec2 bisector = glm::normalize(inwardNormal(p[(v + n - 1) % n], b) + inwardNormal(b, p[(v + 1) % n]));
    double best = std::numeric_limits<double>::infinity(), bestS = 0.0;
    std::size_t hit = n;
    for (std::size_t j = 0; j < n; ++j) {
        if (j == v || (j + 1) % n == v) continue;
        const glm::dvec2 q = p[j], e = p[(j + 1) % n] - q;
        const double den = cross(bisector, e);
        if (den == 0.0) continue;
        const double t = cross(q - b, e) / den, s = cross(q - b, bisector) / den;
        if (s >= 0.0 && s <= 1.0 && t > 1e-9 && t < best) best = t, bestS = s, hit = j;
    }
    if (hit == n) return;
    const std::size_t hitNext = (hit + 1) % n;
    glm::dvec2 h = p[hit] + (p[hitNext] - p[hit]) * bestS;
    // A cut ending close to a vertex ends on it, when that is still a diagonal: no slivers.
    for (std::size_t w : {hit, hitNext}) {
        if (glm::distance(h, p[w]) >= kCutSnap || w == v || w == (v + 1) % n || w == (v + n - 1) % n) continue;
        bool clear = true;
        for (std::size_t j = 0; j < n && clear; ++j) {
            const std::size_t jn = (j + 1) % n;
            if (j == v || jn == v || j == w || jn == w) continue;
            clear = !segmentsCross(b, p[w], p[j], p[jn]);
        }
        if (clear) {
            h = p[w];
            break;
        }
    }
    if (h == p[v]) return;
    auto [first, second] = cutAtReflex(piece, v, hit, h);
    dropCollinear(first);
    dropCollinear(second);
    convexSplit(std::move(first), out, depth + 1);
    convexSplit(std::move(second), out, depth + 1);
}

// A street segment and the distance a lot keeps from it (half its width and the sidewalk).
struct Clearance {
    glm::dvec2 a{0.0}, b{0.0};
    double need = 0.0;
};

// Street segments by the square cells (kClearanceCell metres) that their clearance reaches,
// so that a lot looks only at the streets near it: without it, planning is lots × streets
// (18 s for 100 km², where a tile's own work takes 1 s).
constexpr double kClearanceCell = 64.0;

struct ClearanceGrid {
    std::span<const Clearance> streets;
    std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> cells;

    static std::uint64_t key(long long x, long long y) { return std::uint64_t(x) << 32 ^ std::uint64_t(y & 0xffffffff); }
    static glm::ivec2 cellOf(glm::dvec2 p) { return glm::ivec2(glm::floor(p / kClearanceCell)); }

    explicit ClearanceGrid(std::span<const Clearance> s) : streets(s) {
        for (std::uint32_t i = 0; i < s.size(); ++i) {
            const glm::ivec2 lo = cellOf(glm::min(s[i].a, s[i].b) - s[i].need), hi = cellOf(glm::max(s[i].a, s[i].b) + s[i].need);
            for (int y = lo.y; y <= hi.y; ++y)
                for (int x = lo.x; x <= hi.x; ++x) cells[key(x, y)].push_back(i);
        }
    }
    // The streets whose clearance box may meet the box [lo, hi], ascending: a superset of those
    // that do, so keepClear's own test decides as if it saw them all.
    std::vector<std::uint32_t> near(glm::dvec2 lo, glm::dvec2 hi) const {
        std::vector<std::uint32_t> out;
        const glm::ivec2 a = cellOf(lo), b = cellOf(hi);
        for (int y = a.y; y <= b.y; ++y)
            for (int x = a.x; x <= b.x; ++x)
                if (const auto it = cells.find(key(x, y)); it != cells.end()) out.insert(out.end(), it->second.begin(), it->second.end());
        std::sort(out.begin(), out.end());
        out.erase(std::unique(out.begin(), out.end()), out.end());
        return out;
    }
};

// Shrinks a convex lot until it keeps every street's clearance: a street that ends near a
// block corner without bounding the block (two streets meeting the ring road close
// together) is not on the block's boundary, so the curb does not account for it. Each cut is
// the separating line of the lot and the street segment moved to the clearance, which keeps
// the lot convex. False when the street touches the lot or nothing is left. Streets in order;
// the lot only shrinks, so those the grid leaves out would all be skipped.
bool keepClear(Piece& piece, const ClearanceGrid& grid) {
    glm::dvec2 lo = piece.polygon[0], hi = piece.polygon[0];
    for (glm::dvec2 q : piece.polygon) lo = glm::min(lo, q), hi = glm::max(hi, q);
    for (std::uint32_t index : grid.near(lo, hi)) {
        const Clearance& s = grid.streets[index];
        const Polygon2& p = piece.polygon;
        const std::size_t n = p.size();
        lo = hi = p[0];
        for (glm::dvec2 q : p) lo = glm::min(lo, q), hi = glm::max(hi, q);
        if (std::min(s.a.x, s.b.x) > hi.x + s.need || std::max(s.a.x, s.b.x) < lo.x - s.need ||
            std::min(s.a.y, s.b.y) > hi.y + s.need || std::max(s.a.y, s.b.y) < lo.y - s.need)
            continue;
        if (containsPoint(p, s.a) || containsPoint(p, s.b)) return false;
        double best = std::numeric_limits<double>::infinity();
        glm::dvec2 onLot{0.0}, onStreet{0.0};
        for (std::size_t i = 0; i < n; ++i) {
            const glm::dvec2 a = p[i], b = p[(i + 1) % n];
            if (segmentsCross(a, b, s.a, s.b)) return false;
            const glm::dvec2 q = closestOnSegment(a, s.a, s.b);
            if (glm::distance(a, q) < best) best = glm::distance(a, q), onLot = a, onStreet = q;
            for (glm::dvec2 e : {s.a, s.b}) {
                const glm::dvec2 c = closestOnSegment(e, a, b);
                if (glm::distance(c, e) < best) best = glm::distance(c, e), onLot = c, onStreet = e;
            }
        }
        if (best >= s.need - 1e-7) continue;  // the block's own streets, up to rounding
        if (!(best > 0.0)) return false;
        const glm::dvec2 normal = (onLot - onStreet) / best;
        piece = cutPiece(piece, normal, glm::dot(normal, onStreet) + s.need, false).second;
        if (piece.polygon.size() < 3) return false;
    }
    return true;
}

// The street-facing convex pieces of a block's inner polygon.
std::vector<Piece> convexPieces(const Polygon2& inner) {
    std::vector<Piece> pieces;
    convexSplit({inner, std::vector<bool>(inner.size(), true)}, pieces, 0);
    std::erase_if(pieces, [](const Piece& piece) {
        return longestStreetEdge(piece).first < 0 || !isConvex(piece.polygon);
    });
    return pieces;
}

// The coastline, west to east: smooth value noise about water * depth, kept inside the city
// with room for the promenade.
std::vector<glm::dvec2> coastline(const CityRecipe& recipe, std::uint64_t seed, glm::dvec2 size) {
    const CoastRecipe& coast = recipe.coast;
    const std::uint64_t coastSeed = deriveSeed(seed, "coast");
    const double top = std::max(0.0, size.y - 2.0 * coast.promenadeWidth - 0.5 * recipe.streets.minorSpacing);
    const int samples = std::max(2, static_cast<int>(std::ceil(size.x / kCoastStep)));
    std::vector<glm::dvec2> out;
    for (int k = 0; k <= samples; ++k) {
        const double x = k == samples ? size.x : size.x * k / samples;
        const double q = x / coast.wavelength;
        const double noise = 0.7 * valueNoise(coastSeed, {q, 0.5}) + 0.3 * valueNoise(coastSeed, {2.0 * q, 7.5});
        out.push_back({x, std::clamp(coast.water * size.y + coast.amplitude * noise, 0.0, top)});
    }
    return out;
}

// The blocks: the arrangement's faces on the land, each shrunk to its kerb and its sidewalk's
// inner edge, sorted by centroid (y, then x).
std::vector<Block> blocksOf(std::span<const ArrangementFace> faces, const Land& land, const CityRecipe& recipe) {
    std::vector<Block> blocks;
    for (const ArrangementFace& face : faces) {
        if (face.hasHoles || face.polygon.size() < 3) continue;
        if (!land.contains(interiorPoint(face.polygon))) continue;
        Polygon2 polygon = face.polygon;
        std::vector<double> offset = face.edgeWeight;
        dropCollinear(polygon, offset);
        Block block;
        block.curb = curbPolygon(polygon, offset);
        if (block.curb.empty() || signedArea(block.curb) < recipe.lots.minArea) continue;
        block.inner = insetPolygon(block.curb, recipe.streets.sidewalkWidth);
        if (block.inner.size() < 3 || signedArea(block.inner) < recipe.lots.minArea) continue;
        blocks.push_back(std::move(block));
    }
    std::vector<std::pair<glm::dvec2, std::size_t>> order;
    for (std::size_t i = 0; i < blocks.size(); ++i) order.emplace_back(centroid(blocks[i].curb), i);
    std::sort(order.begin(), order.end(), [](const auto& a, const auto& b) {
        if (a.first.y != b.first.y) return a.first.y < b.first.y;
        if (a.first.x != b.first.x) return a.first.x < b.first.x;
        return a.second < b.second;
    });
    std::vector<Block> sorted;
    sorted.reserve(blocks.size());
    for (const auto& [c, i] : order) sorted.push_back(std::move(blocks[i]));
    return sorted;
}

// Splits every block into lots that keep clear of every street (plan.streets) and numbers
// blocks and lots; reports progress from 0.5 to 1.
void addLots(CityPlan& plan, const CityRecipe& recipe, std::uint64_t seed, const ProgressFn& progress) {
    std::vector<Clearance> clearances;
    for (const Street& street : plan.streets)
        for (std::size_t k = 0; k + 1 < street.polyline.size(); ++k)
            clearances.push_back(
                {street.polyline[k], street.polyline[k + 1], 0.5 * street.width + recipe.streets.sidewalkWidth});
    const ClearanceGrid grid(clearances);
    for (std::size_t b = 0; b < plan.blocks.size(); ++b) {
        Block& block = plan.blocks[b];
        block.id = static_cast<int>(b);
        LotSplitter splitter{recipe.lots, Rng(deriveSeed(seed, "lots", b)), {}};
        for (Piece& piece : convexPieces(block.inner)) splitter.split(std::move(piece), 0);
        for (Piece& piece : splitter.lots) {
            if (!keepClear(piece, grid) || signedArea(piece.polygon) < recipe.lots.minArea) continue;
            const auto [front, length] = longestStreetEdge(piece);
            if (front < 0 || !isConvex(piece.polygon)) continue;
            Lot lot;
            lot.id = static_cast<int>(plan.lots.size());
            lot.block = block.id;
            lot.polygon = std::move(piece.polygon);
            lot.streetEdge = std::move(piece.street);
            lot.frontEdge = front;
            block.lots.push_back(lot.id);
            plan.lots.push_back(std::move(lot));
        }
        if ((b & 15u) == 15u) reportProgress(progress, 0.5 + 0.5 * static_cast<double>(b + 1) / plan.blocks.size());
    }
}

}  // namespace

double coastY(const CityPlan& plan, double x) { return yAt(plan.coastline, x); }

CityPlan planCity(const CityRecipe& recipe, std::uint64_t seed, glm::dvec2 size, const ProgressFn& progress) {
    if (!(std::isfinite(size.x) && std::isfinite(size.y) && size.x > 0.0 && size.y > 0.0))
        throw InputError(format("city size must be positive and finite (got {} x {} m)", size.x, size.y));
    const StreetRecipe& streets = recipe.streets;
    const CoastRecipe& coast = recipe.coast;
    if (!(streets.minorSpacing > 0.0) || !(streets.majorSpacing > 0.0) || !(streets.bendWavelength > 0.0) ||
        !(coast.wavelength > 0.0) || !(recipe.lots.minArea > 0.0))
        throw InputError("recipe: street spacings, wavelengths and lots.min_area must be positive");
    const double gridSide = 2.0 * (std::ceil(0.5 * glm::length(size) / streets.minorSpacing) + 1.0) + 1.0;
    if (gridSide * gridSide > kMaxGridNodes)
        throw InputError(format("city size {} x {} m is too large for a street spacing of {} m", size.x, size.y,
                                streets.minorSpacing));
    reportProgress(progress, 0.0);

    CityPlan plan;
    plan.size = size;
    Land land;
    land.size = size;
    if (coast.water > 0.0) {
        plan.coastline = coastline(recipe, seed, size);
        for (glm::dvec2 p : plan.coastline) land.promenade.push_back({p.x, p.y + 0.5 * coast.promenadeWidth});
    }
    StreetGraph graph = buildStreets(streets, coast.promenadeWidth, land, seed);
    plan.streets = std::move(graph.streets);
    reportProgress(progress, 0.2);

    const std::vector<ArrangementFace> faces = arrangementFaces(graph.segments);
    reportProgress(progress, 0.5);
    plan.blocks = blocksOf(faces, land, recipe);
    addLots(plan, recipe, seed, progress);
    reportProgress(progress, 1.0);
    return plan;
}

}  // namespace dawnforge::procgen
