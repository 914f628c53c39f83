// report.html: the page, section by section, from the files the stages wrote. Each section
// reads its own inputs; what fails to read becomes "not available" in its place.
#include "report.hpp"

#include "report_parts.hpp"

#include <dawnforge/core/atomic_file.hpp>
#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/read_file.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <functional>

namespace dawnforge::cli {

namespace {

namespace fs = std::filesystem;
using report::escapeHtml;
using report::fixed;

// No external font, script or stylesheet: the page stands alone.
constexpr const char* kStyle = R"(
body { font: 15px/1.45 system-ui, sans-serif; margin: 2em auto; max-width: 1320px; padding: 0 1em; color: #222; }
h1 { font-size: 1.6em; } h2 { margin-top: 1.8em; border-bottom: 1px solid #ccc; }
figure { display: inline-block; margin: 0 1em 1em 0; vertical-align: top; }
figure.picture img { max-width: 100%; width: 640px; }
figure.channel img { width: 290px; image-rendering: pixelated; background: #000; }
figcaption { font-size: 0.9em; color: #555; }
table { border-collapse: collapse; } td, th { padding: 0.25em 0.8em; border-bottom: 1px solid #ddd; text-align: left; }
td.n { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
p.na { color: #a33; }
svg { font: 12px system-ui, sans-serif; background: #fff; }
svg .grid { stroke: #e4e4e4; } svg .tick { stroke: #888; } svg .frame { fill: none; stroke: #888; }
svg .bar { fill: #4a7fb0; }
)";

std::string notAvailable(std::string_view why) {
    return format("<p class=\"na\">not available: {}</p>\n", escapeHtml(why));
}

// The section's HTML, or "not available" with what went wrong.
std::string guarded(const std::function<std::string()>& part) {
    try {
        return part();
    } catch (const std::exception& e) {
        return notAvailable(e.what());
    }
}

std::string pngUri(std::span<const std::byte> png) { return "data:image/png;base64," + report::base64(png); }

std::string figure(std::string_view cls, std::string_view uri, std::string_view caption) {
    return format("<figure class=\"{}\"><img src=\"{}\" alt=\"{}\"><figcaption>{}</figcaption></figure>\n", cls, uri,
                  escapeHtml(caption), escapeHtml(caption));
}

std::string picturesSection(const ReportInputs& inputs) {
    std::string s = "<h2 id=\"pictures\">Pictures</h2>\n";
    if (inputs.pictures.empty()) return s + notAvailable("this build renders no pictures");
    for (const ReportPicture& p : inputs.pictures)
        s += guarded([&] {
            const exporters::Image image = exporters::readPng(p.file);  // it decodes, or this throws
            return figure("picture", pngUri(readBinaryFile(p.file)),
                          format("{} ({} × {}, {})", p.caption, image.width, image.height, p.file.filename().string()));
        });
    return s;
}

struct Footprint {
    std::size_t files = 0;
    std::uintmax_t bytes = 0;
    bool missing = false;
};

Footprint footprintOf(const std::vector<fs::path>& outputs, const fs::path& dir) {
    Footprint f;
    for (const fs::path& o : outputs) {
        std::error_code ec;
        const fs::path p = dir / o;
        if (fs::is_regular_file(p, ec)) {
            ++f.files, f.bytes += fs::file_size(p, ec);
        } else if (fs::is_directory(p, ec)) {
            for (fs::recursive_directory_iterator it(p, ec), end; !ec && it != end; it.increment(ec))
                if (it->is_regular_file(ec)) ++f.files, f.bytes += it->file_size(ec);
        } else {
            f.missing = true;
        }
    }
    return f;
}

std::string sizeText(std::uintmax_t bytes) {
    if (bytes >= 1000000) return fixed(double(bytes) / 1e6, 1) + " MB";
    return fixed(double(bytes) / 1e3, 1) + " kB";
}

// `p` as seen from the report's folder.
std::string shownPath(const fs::path& p, const fs::path& dir) {
    const fs::path relative = p.lexically_relative(dir);
    return (relative.empty() ? p : relative).generic_string();
}

constexpr std::size_t kListed = 4;  // outputs named per stage; the rest are counted

std::string stagesSection(const ReportInputs& inputs, const fs::path& dir) {
    std::string s = "<h2 id=\"stages\">Stages</h2>\n";
    if (inputs.stages.empty()) return s + notAvailable("no stage ran");
    s += "<table><tr><th>stage</th><th>made</th><th>outputs</th><th>files</th><th>size</th><th>time (s)</th></tr>\n";
    double total = 0.0;
    for (const ReportStage& st : inputs.stages) {
        const Footprint f = footprintOf(st.outputs, dir);
        std::string outputs;
        for (std::size_t i = 0; i < std::min<std::size_t>(st.outputs.size(), kListed); ++i)
            outputs += (i ? ", " : "") + st.outputs[i].generic_string();
        if (st.outputs.size() > kListed) outputs += format(" and {} more", st.outputs.size() - kListed);
        s += format("<tr><td>{}</td><td>{}</td><td>{}{}</td><td class=\"n\">{}</td><td class=\"n\">{}</td><td class=\"n\">{}</td></tr>\n",
                    escapeHtml(st.name), escapeHtml(st.made), escapeHtml(outputs), f.missing ? " (some missing)" : "",
                    f.files, sizeText(f.bytes), st.seconds >= 0.0 ? fixed(st.seconds, 2) : "-");
        total += std::max(st.seconds, 0.0);
    }
    s += format("<tr><th>total</th><td></td><td></td><td></td><td></td><td class=\"n\">{}</td></tr>\n</table>\n", fixed(total, 2));
    return s + "<p>Times are wall-clock seconds of this run: the one part of the page that differs run to run.</p>\n";
}

nlohmann::json readJson(const fs::path& file) {
    nlohmann::json j = nlohmann::json::parse(readTextFile(file), nullptr, false);
    if (j.is_discarded() || !j.is_object()) throw InputError(format("{}: not a JSON object", file.string()));
    return j;
}

// The receiver of `building` in bake.json, or its first building's when `building` < 0.
const nlohmann::json& bakeReceiver(const nlohmann::json& bake, int building, const fs::path& file) {
    if (bake.contains("receivers") && bake["receivers"].is_array())
        for (const nlohmann::json& r : bake["receivers"])
            if (r.value("kind", "") == "building" && (building < 0 || r.value("building", -1) == building)) return r;
    throw InputError(building < 0 ? format("{} has no building", file.string())
                                  : format("{} has no building {}", file.string(), building));
}

std::string bakeSection(const ReportInputs& inputs, const fs::path& dir) {
    const std::string s = "<h2 id=\"bake\">Baked lighting</h2>\n";
    if (inputs.bakeDir.empty()) return s + notAvailable("no bake");
    return s + guarded([&] {
        const nlohmann::json bake = readJson(inputs.bakeDir / "bake.json");
        const nlohmann::json& r = bakeReceiver(bake, inputs.bakeBuilding, inputs.bakeDir / "bake.json");
        const std::string name = r.at("name").get<std::string>();
        const exporters::Image lightmap = exporters::readPng(inputs.bakeDir / r.at("lightmap").get<std::string>());
        const std::array<exporters::Image, 4> channels = report::splitChannels(lightmap);
        std::string out = format("<p>{}/{}'s lightmap, {} × {} texels: each channel as stored, "
                                 "round(255·sqrt(value / range)); black between the charts.</p>\n",
                                 escapeHtml(shownPath(inputs.bakeDir, dir)), escapeHtml(name), lightmap.width, lightmap.height);
        const char* keys[4] = {"r", "g", "b", "a"};
        for (std::size_t c = 0; c < 4; ++c) {
            const nlohmann::json channel = bake.value("channels", nlohmann::json::object()).value(keys[c], nlohmann::json::object());
            const std::string caption = format("{} ({}, range {})", channel.value("name", std::string(keys[c])),
                                               char(std::toupper(keys[c][0])), channel.value("range", 0.0));
            out += figure("channel", pngUri(exporters::encodePng(channels[c])), caption);
        }
        return out;
    });
}

std::string simulationSummary(const nlohmann::json& sim, const report::Motion& m) {
    const nlohmann::json energy = sim.value("energy", nlohmann::json::object());
    const nlohmann::json glue = sim.value("glue", nlohmann::json::object());
    const nlohmann::json debris = sim.value("debris", nlohmann::json::object());
    const std::size_t chips = debris.value("chips", std::size_t(0));
    const std::size_t puffs = debris.value("dust", nlohmann::json::object()).value("puffs", std::size_t(0));
    return format("<p>{} pieces, {} frames at {} fps; {} of {} bonds broke; {} chips of debris from {} of them and {} puffs of dust; fastest piece {} m/s. "
                  "Energy (sim.json, pieces and projectile less what the triggers put in): initial {} MJ, final {} MJ, "
                  "injected {} MJ. Potential energy of the pieces at frame 0 from transforms.bin: {} MJ.</p>\n",
                  sim.value("pieces", std::size_t(0)) - chips, sim.value("frames", 0), fixed(sim.value("fps", 0.0), 0),
                  glue.value("broken", 0), glue.value("bonds", 0), chips, debris.value("bonds", 0), puffs, fixed(sim.value("max_speed", 0.0), 1), fixed(energy.value("initial", 0.0) / 1e6, 3),
                  fixed(energy.value("final", 0.0) / 1e6, 3), fixed(energy.value("injected", 0.0) / 1e6, 3),
                  fixed(m.potential.front() / 1e6, 3));
}

std::string simulationSection(const ReportInputs& inputs, const fs::path& dir) {
    const std::string s = "<h2 id=\"simulation\">Simulation</h2>\n";
    if (inputs.simDir.empty() || inputs.fractureDir.empty()) return s + notAvailable("no simulation");
    return s + guarded([&] {
        const nlohmann::json sim = readJson(inputs.simDir / "sim.json");
        const report::Motion m = report::readMotion(inputs.simDir, inputs.fractureDir);
        std::vector<double> kinetic, released;
        for (std::size_t k = 0; k < m.time.size(); ++k) {
            kinetic.push_back(m.kinetic[k] / 1e6);
            released.push_back((m.potential.front() - m.potential[k]) / 1e6);
        }
        const std::vector<report::Series> energy{{"kinetic", "#d0582a", kinetic}, {"potential released", "#4a7fb0", released}};
        const std::vector<report::Series> moving{{"pieces in motion", "#2f8f4e", m.moving}};
        return format("<p>From {}/ and {}/.</p>\n", escapeHtml(shownPath(inputs.simDir, dir)), escapeHtml(shownPath(inputs.fractureDir, dir))) +
               simulationSummary(sim, m) +
               report::lineChart("energy of the pieces over time", "time (s)", "energy (MJ)", m.time, energy) +
               report::lineChart("pieces in motion over time", "time (s)", "pieces", m.time, moving) +
               format("<p>Kinetic energy from the frames' central differences (translation and rotation); a piece is in "
                      "motion above {} m/s or {} rad/s.</p>\n",
                      report::kMovingSpeed, report::kMovingSpin);
    });
}

std::string fractureSection(const ReportInputs& inputs, const fs::path& dir) {
    const std::string s = "<h2 id=\"fracture\">Fracture</h2>\n";
    if (inputs.fractureDir.empty()) return s + notAvailable("no fracture");
    return s + guarded([&] {
        const nlohmann::json fracture = readJson(inputs.fractureDir / "fracture.json");
        std::vector<double> volumes;
        for (const nlohmann::json& p : fracture.value("pieces", nlohmann::json::array())) volumes.push_back(p.at("volume").get<double>());
        if (volumes.empty()) throw InputError(format("{} has no pieces", (inputs.fractureDir / "fracture.json").string()));
        std::vector<double> sorted = volumes;
        std::sort(sorted.begin(), sorted.end());
        const report::LogHistogram h = report::logHistogram(volumes, 4);
        const nlohmann::json input = fracture.value("input", nlohmann::json::object());
        return format("<p>{}/fracture.json: {} pieces of {} m³ (the input: {} m³); smallest {} m³, median {} m³, largest {} m³.</p>\n",
                      escapeHtml(shownPath(inputs.fractureDir, dir)), volumes.size(), fixed(fracture.value("volume", 0.0), 2),
                      fixed(input.value("volume", 0.0), 2),
                      fixed(sorted.front(), 4), fixed(sorted[sorted.size() / 2], 4), fixed(sorted.back(), 2)) +
               report::histogramChart("the pieces' volumes", h, "m³") +
               (h.skipped ? format("<p>{} pieces without a positive volume are not counted.</p>\n", h.skipped) : "");
    });
}

}  // namespace

std::string reportHtml(const ReportInputs& inputs, const fs::path& dir) {
    std::string html = format("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>{}</title>\n"
                              "<link rel=\"icon\" href=\"data:,\">\n<style>{}</style>\n</head>\n<body>\n<h1>{}</h1>\n",
                              escapeHtml(inputs.title), kStyle, escapeHtml(inputs.title));
    html += "<p><a href=\"#pictures\">pictures</a> · <a href=\"#stages\">stages</a> · <a href=\"#bake\">baked lighting</a> · "
            "<a href=\"#simulation\">simulation</a> · <a href=\"#fracture\">fracture</a></p>\n";
    html += picturesSection(inputs);
    html += guarded([&] { return stagesSection(inputs, dir); });
    html += bakeSection(inputs, dir) + simulationSection(inputs, dir) + fractureSection(inputs, dir);
    return html + "</body>\n</html>\n";
}

fs::path writeReport(const ReportInputs& inputs, const fs::path& dir) {
    const fs::path file = dir / "report.html";
    writeFileAtomically(file, reportHtml(inputs, dir));
    return file;
}

}  // namespace dawnforge::cli
