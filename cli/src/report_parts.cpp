// Encodings, the histogram, plots (inline SVG) and the bake's channels of report.html.
#include "report_parts.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace dawnforge::cli::report {

std::string base64(std::span<const std::byte> bytes) {
    static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((bytes.size() + 2) / 3 * 4);
    for (std::size_t i = 0; i < bytes.size(); i += 3) {
        const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
        std::uint32_t v = 0;
        for (std::size_t k = 0; k < 3; ++k) v = v << 8 | (k < n ? std::to_integer<std::uint32_t>(bytes[i + k]) : 0u);
        for (std::size_t k = 0; k < 4; ++k) out += k <= n ? kAlphabet[(v >> (18 - 6 * k)) & 63u] : '=';
    }
    return out;
}

std::string escapeHtml(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    for (char c : text) {
        switch (c) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            case '\'': out += "&#39;"; break;
            default: out += c;
        }
    }
    return out;
}

std::string fixed(double v, int decimals) {
    if (!std::isfinite(v)) return "-";
    char text[64];
    std::snprintf(text, sizeof text, "%.*f", std::clamp(decimals, 0, 12), v);
    return text;
}

double LogHistogram::lowerEdge(std::size_t bin) const {
    return std::pow(10.0, firstDecade + double(bin) / perDecade);
}

LogHistogram logHistogram(std::span<const double> values, int perDecade) {
    DAWNFORGE_ASSERT(perDecade >= 1, "perDecade must be at least 1");
    LogHistogram h;
    h.perDecade = perDecade;
    double lo = HUGE_VAL, hi = -HUGE_VAL;
    for (double v : values)
        if (std::isfinite(v) && v > 0.0) lo = std::min(lo, std::log10(v)), hi = std::max(hi, std::log10(v));
        else ++h.skipped;
    if (lo > hi) return h;
    h.firstDecade = int(std::floor(lo));
    const int lastDecade = std::max(h.firstDecade + 1, int(std::ceil(hi)));
    h.counts.assign(std::size_t((lastDecade - h.firstDecade) * perDecade), 0);
    for (double v : values) {
        if (!(std::isfinite(v) && v > 0.0)) continue;
        // A value on an edge goes to the bin above it; the largest stays in the last bin.
        const double at = (std::log10(v) - h.firstDecade) * perDecade;
        const auto bin = std::clamp<long>(long(std::floor(at + 1e-9)), 0, long(h.counts.size()) - 1);
        ++h.counts[std::size_t(bin)];
    }
    return h;
}

double PlotBox::px(double x) const { return left + (x - x0) / (x1 - x0) * width; }
double PlotBox::py(double y) const { return top + height - (y - y0) / (y1 - y0) * height; }

std::string svgPath(std::span<const double> xs, std::span<const double> ys, const PlotBox& box) {
    DAWNFORGE_ASSERT(xs.size() == ys.size(), "one y per x");
    std::string d;
    bool pen = false;
    for (std::size_t i = 0; i < xs.size(); ++i) {
        if (!std::isfinite(xs[i]) || !std::isfinite(ys[i])) {
            pen = false;
            continue;
        }
        if (!d.empty()) d += ' ';
        d += pen ? 'L' : 'M';
        d += fixed(box.px(xs[i]), 1);
        d += ' ';
        d += fixed(box.py(ys[i]), 1);
        pen = true;
    }
    return d;
}

std::vector<double> niceTicks(double lo, double hi, int count) {
    if (!std::isfinite(lo) || !std::isfinite(hi)) return {0.0, 1.0};
    if (hi <= lo) hi = lo + (lo == 0.0 ? 1.0 : std::abs(lo));
    const double raw = (hi - lo) / std::max(count, 1);
    const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
    const double norm = raw / magnitude;
    // d3's tickIncrement: 1, 2, 5 or 10, whichever brings the count nearest to `count`.
    const double step = (norm >= std::sqrt(50.0) ? 10.0 : norm >= std::sqrt(10.0) ? 5.0 : norm >= std::sqrt(2.0) ? 2.0 : 1.0) * magnitude;
    const double first = std::floor(lo / step + 1e-9), last = std::ceil(hi / step - 1e-9);
    std::vector<double> ticks;
    for (double k = first; k <= last; ++k) ticks.push_back(k * step == 0.0 ? 0.0 : k * step);
    return ticks;
}

namespace {

constexpr double kWidth = 640.0, kHeight = 250.0;
constexpr double kLeft = 70.0, kRight = 20.0, kTop = 30.0, kBottom = 44.0;

// Decimals that tell ticks `step` apart.
int decimalsFor(double step) { return std::max(0, int(std::ceil(-std::log10(step) - 1e-9))); }

std::string svgOpen(std::string_view label) {
    return format(R"(<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 {} {}" width="{}" height="{}" role="img" aria-label="{}">)",
                  kWidth, kHeight, kWidth, kHeight, escapeHtml(label)) +
           "\n";
}

std::string text(double x, double y, std::string_view anchor, std::string_view content, std::string_view extra = "") {
    return format(R"(<text x="{}" y="{}" text-anchor="{}"{}>{}</text>)", fixed(x, 1), fixed(y, 1), anchor, extra,
                  escapeHtml(content)) +
           "\n";
}

// Horizontal grid lines with their labels on the left, and the axis titles.
std::string axes(const PlotBox& box, std::span<const double> yTicks, std::string_view xLabel, std::string_view yLabel) {
    std::string s;
    const int decimals = yTicks.size() > 1 ? decimalsFor(yTicks[1] - yTicks[0]) : 0;
    for (double t : yTicks) {
        const double y = box.py(t);
        s += format(R"(<line x1="{}" y1="{}" x2="{}" y2="{}" class="grid"/>)", fixed(box.left, 1), fixed(y, 1),
                    fixed(box.left + box.width, 1), fixed(y, 1)) + "\n";
        s += text(box.left - 6.0, y + 4.0, "end", fixed(t, decimals));
    }
    s += format(R"(<rect x="{}" y="{}" width="{}" height="{}" class="frame"/>)", fixed(box.left, 1), fixed(box.top, 1),
                fixed(box.width, 1), fixed(box.height, 1)) + "\n";
    s += text(box.left + box.width / 2.0, kHeight - 6.0, "middle", xLabel);
    s += text(14.0, box.top + box.height / 2.0, "middle", yLabel,
              format(R"x( transform="rotate(-90 14 {})")x", fixed(box.top + box.height / 2.0, 1)));
    return s;
}

std::string xTick(const PlotBox& box, double x, std::string_view label) {
    const double at = box.px(x);
    return format(R"(<line x1="{}" y1="{}" x2="{}" y2="{}" class="tick"/>)", fixed(at, 1), fixed(box.top + box.height, 1),
                  fixed(at, 1), fixed(box.top + box.height + 5.0, 1)) + "\n" +
           text(at, box.top + box.height + 18.0, "middle", label);
}

PlotBox plotArea() { return {0.0, 1.0, 0.0, 1.0, kLeft, kTop, kWidth - kLeft - kRight, kHeight - kTop - kBottom}; }

}  // namespace

std::string lineChart(std::string_view label, std::string_view xLabel, std::string_view yLabel, std::span<const double> xs,
                      std::span<const Series> series) {
    PlotBox box = plotArea();
    double lo = 0.0, hi = 0.0;
    for (const Series& s : series)
        for (double y : s.ys)
            if (std::isfinite(y)) lo = std::min(lo, y), hi = std::max(hi, y);
    const std::vector<double> yTicks = niceTicks(lo, hi, 5);
    box.y0 = yTicks.front(), box.y1 = yTicks.back();
    box.x0 = xs.empty() ? 0.0 : xs.front(), box.x1 = xs.empty() || xs.back() <= box.x0 ? box.x0 + 1.0 : xs.back();
    std::string s = svgOpen(label) + axes(box, yTicks, xLabel, yLabel);
    const std::vector<double> xTicks = niceTicks(box.x0, box.x1, 8);
    const int decimals = xTicks.size() > 1 ? decimalsFor(xTicks[1] - xTicks[0]) : 0;
    for (double t : xTicks)
        if (t >= box.x0 - 1e-9 && t <= box.x1 + 1e-9) s += xTick(box, t, fixed(t, decimals));
    double legendY = box.top + 14.0;
    for (const Series& line : series) {
        s += format(R"(<path d="{}" fill="none" stroke="{}" stroke-width="1.6"/>)", svgPath(xs, line.ys, box), line.colour) + "\n";
        const double x = box.left + box.width - 150.0;
        s += format(R"(<rect x="{}" y="{}" width="12" height="3" fill="{}"/>)", fixed(x, 1), fixed(legendY - 4.0, 1), line.colour) + "\n";
        s += text(x + 18.0, legendY, "start", line.name);
        legendY += 16.0;
    }
    return s + "</svg>\n";
}

namespace {

// 10^k written out: 0.001, 0.01, ..., 1, 10, 100.
std::string decade(int k) {
    std::string s = k >= 0 ? "1" : "0.";
    s.append(std::size_t(k >= 0 ? k : -k - 1), '0');
    if (k < 0) s += '1';
    return s;
}

}  // namespace

std::string histogramChart(std::string_view label, const LogHistogram& histogram, std::string_view unit) {
    PlotBox box = plotArea();
    const int bins = int(histogram.counts.size());
    const int highest = bins ? *std::max_element(histogram.counts.begin(), histogram.counts.end()) : 0;
    const std::vector<double> yTicks = niceTicks(0.0, std::max(highest, 1), 5);
    box.x0 = histogram.firstDecade, box.x1 = histogram.firstDecade + std::max(1.0, double(bins) / histogram.perDecade);
    box.y0 = 0.0, box.y1 = yTicks.back();
    std::string s = svgOpen(label) + axes(box, yTicks, format("volume ({}, log scale)", unit), "pieces");
    for (int b = 0; b < bins; ++b) {
        const double x0 = box.px(histogram.firstDecade + double(b) / histogram.perDecade);
        const double x1 = box.px(histogram.firstDecade + double(b + 1) / histogram.perDecade);
        const double top = box.py(histogram.counts[std::size_t(b)]);
        s += format(R"(<rect x="{}" y="{}" width="{}" height="{}" class="bar"><title>{} pieces from {} {}</title></rect>)",
                    fixed(x0 + 1.0, 1), fixed(top, 1), fixed(std::max(0.0, x1 - x0 - 2.0), 1),
                    fixed(box.top + box.height - top, 1), histogram.counts[std::size_t(b)],
                    escapeHtml(fixed(histogram.lowerEdge(std::size_t(b)), 6)), escapeHtml(unit)) + "\n";
    }
    for (int k = int(box.x0); k <= int(std::lround(box.x1)); ++k) s += xTick(box, k, decade(k));
    return s + "</svg>\n";
}

std::array<exporters::Image, 4> splitChannels(const exporters::Image& lightmap) {
    DAWNFORGE_ASSERT(lightmap.rgba.size() == std::size_t(lightmap.width) * std::size_t(lightmap.height) * 4, "RGBA8 image");
    std::array<exporters::Image, 4> out;
    for (std::size_t c = 0; c < 4; ++c) {
        out[c].width = lightmap.width, out[c].height = lightmap.height;
        out[c].rgba.resize(lightmap.rgba.size());
        for (std::size_t i = 0; i < lightmap.rgba.size(); i += 4) {
            const std::uint8_t v = lightmap.rgba[i + c];
            out[c].rgba[i] = out[c].rgba[i + 1] = out[c].rgba[i + 2] = v;
            out[c].rgba[i + 3] = 255;
        }
    }
    return out;
}

}  // namespace dawnforge::cli::report
