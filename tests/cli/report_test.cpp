// The parts of report.html that compute (cli/src/report_parts.hpp), and the page over missing,
// damaged and small made-up inputs. The page over a real demo, in a browser: Cli.DemoWritesAValidSceneDeterministically.
#include "test_support.hpp"

#include "report.hpp"
#include "report_parts.hpp"

#include <dawnforge/core/format.hpp>
#include <dawnforge/exporters/image.hpp>

#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <random>

using namespace dawnforge;
using namespace dawnforge::cli;
using dawnforge::test::TempDir;

namespace {

std::vector<std::byte> bytesOf(std::string_view text) {
    std::vector<std::byte> out;
    for (char c : text) out.push_back(std::byte(c));
    return out;
}

std::size_t occurrences(const std::string& text, const std::string& part) {
    std::size_t n = 0;
    for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
    return n;
}

}  // namespace

TEST(Report, Base64IsRfc4648sTestVectors) {
    const std::pair<const char*, const char*> vectors[] = {{"", ""}, {"f", "Zg=="}, {"fo", "Zm8="}, {"foo", "Zm9v"},
                                                           {"foob", "Zm9vYg=="}, {"fooba", "Zm9vYmE="}, {"foobar", "Zm9vYmFy"}};
    for (const auto& [plain, encoded] : vectors) EXPECT_EQ(report::base64(bytesOf(plain)), encoded) << plain;
    const std::vector<std::byte> high{std::byte{0xff}, std::byte{0xfe}, std::byte{0xfd}};
    EXPECT_EQ(report::base64(high), "//79");
}

TEST(Report, EscapesHtml) {
    EXPECT_EQ(report::escapeHtml(R"(<a href="x">Tom & 'Jerry'</a>)"), "&lt;a href=&quot;x&quot;&gt;Tom &amp; &#39;Jerry&#39;&lt;/a&gt;");
}

TEST(Report, LogHistogramCountsEachValueOnceInTheBinOfItsDecade) {
    const std::vector<double> values{0.001, 0.0015, 0.01, 0.5, 1.0, 9.99, 10.0, 0.0, -1.0, std::nan("")};
    const report::LogHistogram h = report::logHistogram(values, 1);
    EXPECT_EQ(h.firstDecade, -3);
    EXPECT_EQ(h.counts, (std::vector<int>{2, 1, 1, 3}));  // [1e-3, 1e-2), [1e-2, 0.1), [0.1, 1), [1, 10]
    EXPECT_EQ(h.skipped, 3);
    EXPECT_TRUE(report::logHistogram(std::vector<double>{}, 4).counts.empty());
}

// Property: for random volumes over six decades, every value lies between the edges of the
// bin that counts it (the edges computed here with pow, not by the histogram's own log10).
TEST(Report, LogHistogramBinsHoldTheirValuesForRandomVolumes) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> exponent(-4.0, 2.0);
    std::vector<double> values;
    for (int i = 0; i < 2000; ++i) values.push_back(std::pow(10.0, exponent(rng)));
    const report::LogHistogram h = report::logHistogram(values, 4);
    std::vector<int> expected(h.counts.size(), 0);
    for (double v : values) {
        std::size_t bin = 0;
        while (bin + 1 < h.counts.size() && v >= std::pow(10.0, h.firstDecade + double(bin + 1) / 4.0)) ++bin;
        ASSERT_GE(v, std::pow(10.0, h.firstDecade + double(bin) / 4.0) * (1.0 - 1e-12));
        ++expected[bin];
    }
    EXPECT_EQ(h.counts, expected);
    EXPECT_EQ(h.counts.size(), 24u);  // 1e-4 to 1e2 in quarters
}

TEST(Report, SvgPathOfAKnownSeriesAndABreakWhereAValueIsMissing) {
    const report::PlotBox box{0.0, 10.0, 0.0, 100.0, 10.0, 20.0, 100.0, 50.0};
    const std::vector<double> xs{0.0, 5.0, 10.0};
    EXPECT_EQ(report::svgPath(xs, std::vector<double>{0.0, 50.0, 100.0}, box), "M10.0 70.0 L60.0 45.0 L110.0 20.0");
    EXPECT_EQ(report::svgPath(xs, std::vector<double>{0.0, std::nan(""), 100.0}, box), "M10.0 70.0 M110.0 20.0");
    EXPECT_EQ(report::svgPath({}, {}, box), "");
}

TEST(Report, NiceTicksAreRoundAndCoverTheRange) {
    EXPECT_EQ(report::niceTicks(0.0, 7.3, 5), (std::vector<double>{0.0, 2.0, 4.0, 6.0, 8.0}));
    EXPECT_EQ(report::niceTicks(-3.0, 97.0, 5), (std::vector<double>{-20.0, 0.0, 20.0, 40.0, 60.0, 80.0, 100.0}));
    EXPECT_EQ(report::niceTicks(0.0, 0.0, 5).front(), 0.0);
    EXPECT_GE(report::niceTicks(0.0, 0.0, 5).back(), 1.0);
}

TEST(Report, ChartsDrawOneLinePerSeriesAndOneBarPerBin) {
    const std::vector<double> xs{0.0, 1.0, 2.0};
    const std::vector<report::Series> series{{"a", "#f00", {1.0, 2.0, 3.0}}, {"b", "#00f", {0.0, -1.0, 4.0}}};
    const std::string line = report::lineChart("two <lines>", "t", "y", xs, series);
    EXPECT_EQ(occurrences(line, "<path d=\"M"), 2u);
    EXPECT_NE(line.find("aria-label=\"two &lt;lines&gt;\""), std::string::npos);
    const report::LogHistogram h = report::logHistogram(std::vector<double>{0.01, 0.02, 3.0}, 2);
    const std::string bars = report::histogramChart("sizes", h, "m³");
    EXPECT_EQ(occurrences(bars, "class=\"bar\""), h.counts.size());
    EXPECT_NE(bars.find(">0.01<"), std::string::npos);  // the decades are labelled
    EXPECT_NE(bars.find(">10<"), std::string::npos);
}

namespace {

// One piece falling freely from 10 m (its inertia diag(3, 5, 7)) while it spins at 2 rad/s
// about y, and one at rest on the ground.
std::vector<float> fallingAndResting(int frames, double fps) {
    std::vector<float> t;
    for (int k = 0; k < frames; ++k) {
        const double s = k / fps;
        const glm::dquat q = glm::angleAxis(2.0 * s, glm::dvec3(0.0, 1.0, 0.0));
        for (double v : {1.0, 10.0 - 0.5 * 9.81 * s * s, 0.0, q.x, q.y, q.z, q.w}) t.push_back(float(v));
        for (double v : {5.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0}) t.push_back(float(v));
    }
    return t;
}

const std::vector<report::PieceMass> kTwoPieces{{2.0, {3.0, 0.0, 0.0, 0.0, 5.0, 0.0, 0.0, 0.0, 7.0}},
                                                {4.0, {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0}}};

}  // namespace

TEST(Report, FreeFallKeepsItsEnergyAndSpinAddsHalfIOmegaSquared) {
    const int frames = 30;
    const report::Motion m = report::motionOf(fallingAndResting(frames, 30.0), kTwoPieces, frames, 30.0);
    ASSERT_EQ(m.time.size(), std::size_t(frames));
    EXPECT_NEAR(m.potential[0], 2.0 * 9.81 * 10.0, 1e-3);
    const double spin = 0.5 * 5.0 * 2.0 * 2.0;  // about y: I_yy ω²/2 = 10 J
    for (int k = 1; k + 1 < frames; ++k) {
        // Central differences of a parabola are exact: kinetic + potential stays m·g·10 (float positions).
        EXPECT_NEAR(m.kinetic[k] - spin + m.potential[k], m.potential[0], 2e-3 * m.potential[0]) << k;
        EXPECT_EQ(m.moving[k], 1.0) << k;  // the falling one; the resting one never counts
    }
    EXPECT_NEAR(m.time.back(), 29.0 / 30.0, 1e-12);
}

TEST(Report, ReadMotionRefusesFilesThatDisagree) {
    TempDir dir;
    std::filesystem::create_directories(dir / "sim");
    std::filesystem::create_directories(dir / "fracture");
    nlohmann::json fracture = {{"pieces", nlohmann::json::array()}};
    for (const report::PieceMass& p : kTwoPieces)
        fracture["pieces"].push_back({{"mass", p.mass},
                                      {"volume", p.mass / 2400.0},
                                      {"inertia", {{p.inertia[0], 0, 0}, {0, p.inertia[4], 0}, {0, 0, p.inertia[8]}}}});
    test::writeText(dir / "fracture" / "fracture.json", fracture.dump());
    test::writeText(dir / "sim" / "sim.json", nlohmann::json{{"frames", 10}, {"fps", 30.0}, {"pieces", 2}}.dump());
    const std::vector<float> t = fallingAndResting(10, 30.0);
    test::writeText(dir / "sim" / "transforms.bin", std::string(reinterpret_cast<const char*>(t.data()), t.size() * 4));
    EXPECT_NEAR(report::readMotion(dir / "sim", dir / "fracture").potential[0], 196.2, 1e-3);
    test::writeText(dir / "sim" / "transforms.bin", std::string(reinterpret_cast<const char*>(t.data()), t.size() * 4 - 4));
    EXPECT_TRUE(test::contains(test::inputErrorOf([&] { report::readMotion(dir / "sim", dir / "fracture"); }), "bytes, expected"));
    test::writeText(dir / "sim" / "sim.json", nlohmann::json{{"frames", 10}, {"fps", 30.0}, {"pieces", 3}}.dump());
    EXPECT_TRUE(test::contains(test::inputErrorOf([&] { report::readMotion(dir / "sim", dir / "fracture"); }), "do not match"));
    // A third "piece" that is a chip of debris: the fracture's two are read, the chip's values skipped.
    test::writeText(dir / "sim" / "sim.json",
                    nlohmann::json{{"frames", 10}, {"fps", 30.0}, {"pieces", 3}, {"debris", {{"chips", 1}}}}.dump());
    std::vector<float> three;
    for (int k = 0; k < 10; ++k) {
        three.insert(three.end(), t.begin() + k * 14, t.begin() + (k + 1) * 14);
        three.insert(three.end(), {1e6f, 1e6f, 1e6f, 0.0f, 0.0f, 0.0f, 1.0f});  // far up: it would dwarf the energy
    }
    test::writeText(dir / "sim" / "transforms.bin", std::string(reinterpret_cast<const char*>(three.data()), three.size() * 4));
    EXPECT_NEAR(report::readMotion(dir / "sim", dir / "fracture").potential[0], 196.2, 1e-3);
    EXPECT_TRUE(test::contains(test::inputErrorOf([&] { report::readMotion(dir / "none", dir / "fracture"); }), "no such file"));
}

TEST(Report, SplitChannelsGivesEachChannelAsOpaqueGrey) {
    exporters::Image lightmap{2, 1, {10, 20, 30, 40, 50, 60, 70, 0}};
    const auto channels = report::splitChannels(lightmap);
    for (std::size_t c = 0; c < 4; ++c) {
        EXPECT_EQ(channels[c].width, 2);
        EXPECT_EQ(channels[c].rgba, (std::vector<std::uint8_t>{lightmap.rgba[c], lightmap.rgba[c], lightmap.rgba[c], 255,
                                                                lightmap.rgba[4 + c], lightmap.rgba[4 + c], lightmap.rgba[4 + c], 255}))
            << c;
    }
}

// Nothing there at all: every part says "not available", and the page is still a page.
TEST(Report, MissingInputsAreNotAvailableNotAnError) {
    TempDir dir;
    ReportInputs inputs;
    inputs.title = "nothing <here>";
    inputs.pictures = {{"gone", dir / "render.png"}};
    inputs.stages = {{"city", "a district", {"city"}, 1.5}};
    inputs.bakeDir = dir / "city" / "bake";
    inputs.fractureDir = dir / "fracture";
    inputs.simDir = dir / "sim";
    const std::string html = reportHtml(inputs, dir.path());
    EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
    EXPECT_NE(html.find("<title>nothing &lt;here&gt;</title>"), std::string::npos);
    EXPECT_EQ(occurrences(html, "not available"), 4u);  // the picture, the bake, the simulation, the fracture
    EXPECT_NE(html.find("(some missing)"), std::string::npos);
    EXPECT_EQ(occurrences(html, "<img"), 0u);
    const auto file = writeReport(ReportInputs{}, dir.path());
    EXPECT_EQ(file, dir / "report.html");
    EXPECT_NE(test::readText(file).find("no stage ran"), std::string::npos);
}

// A damaged picture is not available; the good one beside it is inlined, byte for byte.
TEST(Report, ADamagedPictureIsLeftOutAndAGoodOneInlined) {
    TempDir dir;
    const exporters::Image image{3, 2, std::vector<std::uint8_t>(24, 128)};
    exporters::writePng(image, dir / "good.png");
    std::string damaged = test::readText(dir / "good.png");
    damaged.resize(damaged.size() / 2);
    test::writeText(dir / "bad.png", damaged);
    ReportInputs inputs;
    inputs.pictures = {{"good", dir / "good.png"}, {"bad", dir / "bad.png"}};
    const std::string html = reportHtml(inputs, dir.path());
    EXPECT_EQ(occurrences(html, "<img"), 1u);
    EXPECT_NE(html.find("data:image/png;base64," + report::base64(exporters::encodePng(image))), std::string::npos);
    EXPECT_TRUE(test::contains(html, "not available: ") && test::contains(html, "bad.png"));
}
