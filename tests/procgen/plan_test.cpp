// Properties of the city plan (plan.hpp): blocks tile the land without overlapping, lots are
// convex, on a street, clear of every street, and inside their block; nothing is in the sea;
// the plan is a pure function of (recipe, seed, size).
#include <dawnforge/procgen/plan.hpp>

#include <dawnforge/core/error.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <string>

namespace dawnforge::procgen {
namespace {

bool segmentsCross(glm::dvec2 p1, glm::dvec2 p2, glm::dvec2 q1, glm::dvec2 q2) {
    const double d1 = cross(q2 - q1, p1 - q1), d2 = cross(q2 - q1, p2 - q1);
    const double d3 = cross(p2 - p1, q1 - p1), d4 = cross(p2 - p1, q2 - p1);
    return ((d1 > 0) != (d2 > 0)) && ((d3 > 0) != (d4 > 0));
}

double segmentDistance(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c, glm::dvec2 d) {
    if (segmentsCross(a, b, c, d)) return 0.0;
    return std::min({distanceToSegment(a, c, d), distanceToSegment(b, c, d), distanceToSegment(c, a, b),
                     distanceToSegment(d, a, b)});
}

struct Case {
    std::string name;
    CityRecipe recipe;
    std::uint64_t seed;
    glm::dvec2 size;
};

std::vector<Case> cases() {
    std::vector<Case> out;
    out.push_back({"coast 400x300", CityRecipe{}, 1, {400.0, 300.0}});
    Case inland{"inland 600x600", CityRecipe{}, 2, {600.0, 600.0}};
    inland.recipe.coast.water = 0.0;
    out.push_back(inland);
    Case rotated{"rotated coast 500x420", CityRecipe{}, 3, {500.0, 420.0}};
    rotated.recipe.streets.angle = 27.0;
    rotated.recipe.coast.amplitude = 45.0;
    rotated.recipe.coast.wavelength = 250.0;
    out.push_back(rotated);
    return out;
}

// Each case is planned once for the whole test executable.
const CityPlan& planOf(const Case& c) {
    static std::map<std::string, CityPlan> plans;
    auto it = plans.find(c.name);
    if (it == plans.end()) it = plans.emplace(c.name, planCity(c.recipe, c.seed, c.size)).first;
    return it->second;
}

double landArea(const CityPlan& plan) {
    double sea = 0.0;
    for (std::size_t i = 0; i + 1 < plan.coastline.size(); ++i) {
        const glm::dvec2 a = plan.coastline[i], b = plan.coastline[i + 1];
        sea += 0.5 * (a.y + b.y) * (b.x - a.x);
    }
    return plan.size.x * plan.size.y - sea;
}

TEST(Plan, HasStreetsBlocksAndLots) {
    for (const Case& c : cases()) {
        SCOPED_TRACE(c.name);
        const CityPlan& plan = planOf(c);
        EXPECT_EQ(plan.size, c.size);
        EXPECT_GT(plan.streets.size(), 4u);
        EXPECT_GT(plan.blocks.size(), 4u);
        EXPECT_GT(plan.lots.size(), 4 * plan.blocks.size());
        for (std::size_t i = 0; i < plan.streets.size(); ++i) {
            const Street& s = plan.streets[i];
            EXPECT_EQ(s.id, static_cast<int>(i));
            EXPECT_GE(s.polyline.size(), 2u);
            EXPECT_EQ(s.width, s.major ? (i == 0 && !plan.coastline.empty() ? c.recipe.coast.promenadeWidth
                                                                               : c.recipe.streets.majorWidth)
                                       : c.recipe.streets.minorWidth);
            for (glm::dvec2 p : s.polyline) {  // clipped to the city
                EXPECT_GE(p.x, -1e-9);
                EXPECT_LE(p.x, c.size.x + 1e-9);
                EXPECT_GE(p.y, -1e-9);
                EXPECT_LE(p.y, c.size.y + 1e-9);
            }
        }
    }
}

TEST(Plan, BlocksAreSortedAndDoNotOverlap) {
    for (const Case& c : cases()) {
        SCOPED_TRACE(c.name);
        const CityPlan& plan = planOf(c);
        double area = 0.0;
        for (std::size_t i = 0; i < plan.blocks.size(); ++i) {
            const Block& b = plan.blocks[i];
            EXPECT_EQ(b.id, static_cast<int>(i));
            EXPECT_GT(signedArea(b.curb), 0.0);
            EXPECT_TRUE(isSimple(b.curb));
            EXPECT_GT(signedArea(b.inner), 0.0);
            EXPECT_LT(signedArea(b.inner), signedArea(b.curb));
            area += signedArea(b.curb);
            const glm::dvec2 ci = centroid(b.curb);
            if (i > 0) {
                const glm::dvec2 cp = centroid(plan.blocks[i - 1].curb);
                EXPECT_TRUE(cp.y < ci.y || (cp.y == ci.y && cp.x < ci.x)) << "block " << i;
            }
            for (std::size_t j = 0; j < plan.blocks.size(); ++j)
                if (j != i) {
                    EXPECT_FALSE(containsPoint(plan.blocks[j].curb, ci)) << i << " in " << j;
                }
        }
        EXPECT_LE(area, landArea(plan));
        EXPECT_GT(area, 0.4 * landArea(plan));  // the blocks cover most of the land
    }
}

TEST(Plan, LotsAreConvexOnAStreetAndInsideTheirBlock) {
    for (const Case& c : cases()) {
        SCOPED_TRACE(c.name);
        const CityPlan& plan = planOf(c);
        std::size_t listed = 0;
        for (const Block& b : plan.blocks) {
            listed += b.lots.size();
            for (int id : b.lots) EXPECT_EQ(plan.lots[static_cast<std::size_t>(id)].block, b.id);
        }
        EXPECT_EQ(listed, plan.lots.size());
        for (std::size_t i = 0; i < plan.lots.size(); ++i) {
            const Lot& lot = plan.lots[i];
            EXPECT_EQ(lot.id, static_cast<int>(i));
            const Polygon2& inner = plan.blocks[static_cast<std::size_t>(lot.block)].inner;
            const Polygon2& p = lot.polygon;
            ASSERT_GE(p.size(), 3u);
            EXPECT_TRUE(isConvex(p)) << "lot " << i;
            EXPECT_GT(signedArea(p), 0.0) << "lot " << i;
            EXPECT_GE(signedArea(p), c.recipe.lots.minArea) << "lot " << i;
            for (glm::dvec2 q : p)
                EXPECT_TRUE(containsPoint(inner, q) || distanceToBoundary(inner, q) <= 1e-6) << "lot " << i;
            ASSERT_EQ(lot.streetEdge.size(), p.size());
            ASSERT_GE(lot.frontEdge, 0);
            ASSERT_LT(lot.frontEdge, static_cast<int>(p.size()));
            EXPECT_TRUE(lot.streetEdge[static_cast<std::size_t>(lot.frontEdge)]);
            double longest = 0.0;
            for (std::size_t e = 0; e < p.size(); ++e) {
                const glm::dvec2 a = p[e], b = p[(e + 1) % p.size()];
                const double onBoundary = std::max({distanceToBoundary(inner, a), distanceToBoundary(inner, b),
                                                    distanceToBoundary(inner, 0.5 * (a + b))});
                if (lot.streetEdge[e]) {
                    EXPECT_LE(onBoundary, 1e-6) << "lot " << i << " edge " << e;
                    longest = std::max(longest, glm::distance(a, b));
                } else {
                    EXPECT_GT(distanceToBoundary(inner, 0.5 * (a + b)), 1e-6) << "lot " << i << " edge " << e;
                }
            }
            const glm::dvec2 f0 = p[static_cast<std::size_t>(lot.frontEdge)];
            const glm::dvec2 f1 = p[(static_cast<std::size_t>(lot.frontEdge) + 1) % p.size()];
            EXPECT_EQ(glm::distance(f0, f1), longest);
        }
    }
}

TEST(Plan, LotsOfABlockDoNotOverlap) {
    for (const Case& c : cases()) {
        SCOPED_TRACE(c.name);
        const CityPlan& plan = planOf(c);
        for (const Block& b : plan.blocks) {
            double area = 0.0;
            for (int i : b.lots) {
                const Polygon2& pi = plan.lots[static_cast<std::size_t>(i)].polygon;
                area += signedArea(pi);
                const glm::dvec2 ci = centroid(pi);
                for (int j : b.lots)
                    if (j != i) {
                        EXPECT_FALSE(containsPoint(plan.lots[static_cast<std::size_t>(j)].polygon, ci))
                            << "lot " << i << " in " << j;
                    }
            }
            EXPECT_LE(area, signedArea(b.inner) + 1e-6) << "block " << b.id;
        }
    }
}

TEST(Plan, LotsKeepClearOfEveryStreet) {
    for (const Case& c : cases()) {
        SCOPED_TRACE(c.name);
        const CityPlan& plan = planOf(c);
        const double sidewalk = c.recipe.streets.sidewalkWidth;
        for (const Street& s : plan.streets) {
            const double need = 0.5 * s.width + sidewalk - 1e-6;
            for (std::size_t k = 0; k + 1 < s.polyline.size(); ++k) {
                const glm::dvec2 a = s.polyline[k], b = s.polyline[k + 1];
                for (const Lot& lot : plan.lots) {
                    const Polygon2& p = lot.polygon;
                    EXPECT_FALSE(containsPoint(p, a)) << "street " << s.id << " in lot " << lot.id;
                    double d = std::numeric_limits<double>::infinity();
                    for (std::size_t e = 0; e < p.size(); ++e)
                        d = std::min(d, segmentDistance(p[e], p[(e + 1) % p.size()], a, b));
                    EXPECT_GE(d, need) << "street " << s.id << " lot " << lot.id;
                }
            }
        }
    }
}

TEST(Plan, NothingInTheSea) {
    for (const Case& c : cases()) {
        SCOPED_TRACE(c.name);
        const CityPlan& plan = planOf(c);
        if (c.recipe.coast.water == 0.0) {
            EXPECT_TRUE(plan.coastline.empty());
            EXPECT_EQ(coastY(plan, 0.5 * c.size.x), -std::numeric_limits<double>::infinity());
            continue;
        }
        ASSERT_GE(plan.coastline.size(), 2u);
        EXPECT_EQ(plan.coastline.front().x, 0.0);
        EXPECT_EQ(plan.coastline.back().x, c.size.x);
        for (std::size_t i = 0; i + 1 < plan.coastline.size(); ++i)
            EXPECT_LT(plan.coastline[i].x, plan.coastline[i + 1].x);
        for (glm::dvec2 p : plan.coastline) EXPECT_EQ(coastY(plan, p.x), p.y);
        for (const Block& b : plan.blocks)
            for (glm::dvec2 p : b.curb) EXPECT_GT(p.y, coastY(plan, p.x)) << "block " << b.id;
        for (const Lot& lot : plan.lots)
            for (glm::dvec2 p : lot.polygon) EXPECT_GT(p.y, coastY(plan, p.x)) << "lot " << lot.id;
        // No street centre line south of the promenade's, whose seaward kerb is the coastline.
        const double promenade = 0.5 * c.recipe.coast.promenadeWidth;
        for (const Street& s : plan.streets)
            for (glm::dvec2 p : s.polyline) EXPECT_GE(p.y, coastY(plan, p.x) + promenade - 1e-6) << s.id;
        for (glm::dvec2 p : plan.streets[0].polyline) EXPECT_NEAR(p.y, coastY(plan, p.x) + promenade, 1e-9);
    }
}

void expectSamePlan(const CityPlan& a, const CityPlan& b) {
    const auto samePoints = [](const std::vector<glm::dvec2>& p, const std::vector<glm::dvec2>& q) {
        if (p.size() != q.size()) return false;
        for (std::size_t i = 0; i < p.size(); ++i)
            if (p[i].x != q[i].x || p[i].y != q[i].y) return false;
        return true;
    };
    EXPECT_TRUE(samePoints(a.coastline, b.coastline));
    ASSERT_EQ(a.streets.size(), b.streets.size());
    for (std::size_t i = 0; i < a.streets.size(); ++i) {
        EXPECT_EQ(a.streets[i].major, b.streets[i].major);
        EXPECT_EQ(a.streets[i].width, b.streets[i].width);
        EXPECT_TRUE(samePoints(a.streets[i].polyline, b.streets[i].polyline)) << "street " << i;
    }
    ASSERT_EQ(a.blocks.size(), b.blocks.size());
    for (std::size_t i = 0; i < a.blocks.size(); ++i) {
        EXPECT_TRUE(samePoints(a.blocks[i].curb, b.blocks[i].curb)) << "block " << i;
        EXPECT_TRUE(samePoints(a.blocks[i].inner, b.blocks[i].inner)) << "block " << i;
        EXPECT_EQ(a.blocks[i].lots, b.blocks[i].lots);
    }
    ASSERT_EQ(a.lots.size(), b.lots.size());
    for (std::size_t i = 0; i < a.lots.size(); ++i) {
        EXPECT_EQ(a.lots[i].block, b.lots[i].block);
        EXPECT_TRUE(samePoints(a.lots[i].polygon, b.lots[i].polygon)) << "lot " << i;
        EXPECT_EQ(a.lots[i].streetEdge, b.lots[i].streetEdge);
        EXPECT_EQ(a.lots[i].frontEdge, b.lots[i].frontEdge);
    }
}

TEST(Plan, IsAFunctionOfRecipeSeedAndSize) {
    for (const Case& c : cases()) {
        SCOPED_TRACE(c.name);
        expectSamePlan(planOf(c), planCity(c.recipe, c.seed, c.size));
        const CityPlan other = planCity(c.recipe, c.seed + 100, c.size);
        bool differs = other.lots.size() != planOf(c).lots.size() || other.streets.size() != planOf(c).streets.size();
        for (std::size_t i = 0; !differs && i < other.lots.size(); ++i)
            differs = other.lots[i].polygon != planOf(c).lots[i].polygon;
        EXPECT_TRUE(differs);
    }
}

TEST(Plan, ReportsProgressAndStopsWhenAsked) {
    const Case c = cases()[0];
    double last = -1.0;
    bool monotonic = true;
    planCity(c.recipe, c.seed, c.size, [&](double f) {
        monotonic = monotonic && f >= last;
        last = f;
        return true;
    });
    EXPECT_TRUE(monotonic);
    EXPECT_EQ(last, 1.0);
    EXPECT_THROW(planCity(c.recipe, c.seed, c.size, [](double) { return false; }), Cancelled);
}

TEST(Plan, RejectsABadSize) {
    const CityRecipe recipe;
    const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
    for (glm::dvec2 size : {glm::dvec2(0.0, 100.0), glm::dvec2(100.0, -5.0), glm::dvec2(nan, 100.0),
                            glm::dvec2(100.0, inf)}) {
        try {
            planCity(recipe, 1, size);
            ADD_FAILURE() << "no error for " << size.x << " x " << size.y;
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find("size"), std::string::npos) << e.what();
        }
    }
}

// Timing and counts for a 1 km city (run with --gtest_also_run_disabled_tests).
}  // namespace
}  // namespace dawnforge::procgen
