#pragma once
// The parts of report.html that compute something: encodings, the pieces' histogram, plots,
// the simulation's motion per frame and the bake's channels. report.cpp assembles the page
// from them; tests/cli/report_test.cpp tests them alone.
#include <dawnforge/exporters/image.hpp>

#include <array>
#include <cstddef>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace dawnforge::cli::report {

// RFC 4648 base64 with padding: the payload of a data: URI.
std::string base64(std::span<const std::byte> bytes);
// Text safe in HTML content and attribute values (& < > " ' escaped).
std::string escapeHtml(std::string_view text);
// `v` with `decimals` digits after the point ("-" when not finite).
std::string fixed(double v, int decimals);

// Values counted on a log10 scale, `perDecade` bins a decade, from the decade boundary at or
// below the smallest value to the one at or above the largest. Values that are not finite and
// positive are counted in `skipped`, not in a bin.
struct LogHistogram {
    int firstDecade = 0;  // the lowest bin starts at 10^firstDecade
    int perDecade = 1;
    std::vector<int> counts;
    int skipped = 0;
    double lowerEdge(std::size_t bin) const;  // 10^(firstDecade + bin / perDecade)
};
LogHistogram logHistogram(std::span<const double> values, int perDecade);

// A plot's data range drawn into a box of pixels (y grows upwards in data, downwards on screen).
struct PlotBox {
    double x0 = 0.0, x1 = 1.0, y0 = 0.0, y1 = 1.0;        // data range
    double left = 0.0, top = 0.0, width = 1.0, height = 1.0;  // pixels
    double px(double x) const;
    double py(double y) const;
};
// SVG path data "M x y L x y ..." through the points, pixels with one decimal; points that
// are not finite break the line (the next finite point starts with M).
std::string svgPath(std::span<const double> xs, std::span<const double> ys, const PlotBox& box);
// Evenly spaced round values (1, 2 or 5 × 10^k apart) covering [lo, hi], about `count` of them.
std::vector<double> niceTicks(double lo, double hi, int count);

// One line of a chart.
struct Series {
    std::string name;
    std::string colour;  // CSS colour
    std::vector<double> ys;
};
// An inline SVG line chart of `series` over `xs`, with axes, ticks, labels and a legend.
std::string lineChart(std::string_view label, std::string_view xLabel, std::string_view yLabel,
                      std::span<const double> xs, std::span<const Series> series);
// An inline SVG bar chart of `histogram`, the x axis in decades of `unit`.
std::string histogramChart(std::string_view label, const LogHistogram& histogram, std::string_view unit);

// Per frame of a simulation, from the pieces' transforms (transforms.bin's layout) and their
// masses and inertias about the centre of mass at rest (fracture.json's).
struct Motion {
    std::vector<double> time;       // s
    std::vector<double> kinetic;    // J: translation and rotation of the pieces
    std::vector<double> potential;  // J: m·g·y of the pieces' centres (y up, g 9.81)
    std::vector<double> moving;     // pieces faster than kMovingSpeed or turning faster than kMovingSpin
};
inline constexpr double kMovingSpeed = 0.05;  // m/s
inline constexpr double kMovingSpin = 0.05;   // rad/s
struct PieceMass {
    double mass = 0.0;
    std::array<double, 9> inertia{};  // row-major, world axes at rest
};
// Velocities are central differences of the frames (one-sided at the first and last), so a
// piece in free fall keeps kinetic + potential exactly at every inner frame.
Motion motionOf(std::span<const float> transforms, std::span<const PieceMass> pieces, int frames, double fps);
// Reads SIM_DIR/sim.json and transforms.bin and FRACTURE_DIR/fracture.json; throws InputError
// when one is missing or they disagree (piece count, the file's size).
Motion readMotion(const std::filesystem::path& simDir, const std::filesystem::path& fractureDir);

// A lightmap's four channels (R sky, G sun bounce, B AO, A lamps) as opaque grey images.
std::array<exporters::Image, 4> splitChannels(const exporters::Image& lightmap);

}  // namespace dawnforge::cli::report
