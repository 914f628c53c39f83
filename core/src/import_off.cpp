// OFF import through CGAL's polygon-soup reader (CGAL/IO/OFF.h): points and faces only;
// normals, colours and texture coordinates in the file are read and dropped.
#include "import_off.hpp"

#include <dawnforge/core/error.hpp>
#include <dawnforge/core/format.hpp>
#include <dawnforge/core/read_file.hpp>

#include <CGAL/IO/OFF.h>
#include <CGAL/Simple_cartesian.h>

#include <charconv>
#include <limits>
#include <optional>
#include <sstream>

namespace dawnforge::detail {
namespace {

using Point = CGAL::Simple_cartesian<double>::Point_3;

// CGAL's reader sizes its arrays from the header before it reads a line: counts the text
// cannot hold (a vertex line is at least two bytes per coordinate, a face line at least
// four) are refused first, so that a 309-byte file claiming 353535235358 vertices
// (assimp-testmodels' invalid/OutOfMemory.off) does not take all memory.
void checkOffHeader(const std::string& text, const std::string& name) {
    std::istringstream in(text);
    std::string token;
    std::vector<std::string> tokens;
    while (tokens.size() < 4 && in >> token) {
        if (token.starts_with("#")) {
            std::getline(in, token);
            continue;
        }
        tokens.push_back(token);
    }
    std::size_t at = 0;
    int dimensions = 3;
    if (!tokens.empty() && tokens[0].ends_with("OFF")) {
        if (tokens[0].find('n') != std::string::npos) ++at;  // nOFF: a dimension comes first
        if (tokens[0].find('4') != std::string::npos) ++dimensions;
        ++at;
    }
    auto count = [&](std::size_t i) -> std::optional<unsigned long long> {
        unsigned long long n = 0;
        if (i >= tokens.size()) return std::nullopt;
        const std::string& t = tokens[i];
        const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), n);
        if (ec == std::errc::result_out_of_range) return std::numeric_limits<unsigned long long>::max();
        if (ec != std::errc() || end == t.data()) return std::nullopt;
        return n;
    };
    const auto vertices = count(at), faces = count(at + 1);
    if (!vertices || !faces) throw InputError(format("{}: not a readable OFF file: no vertex and face counts", name));
    const auto bytes = static_cast<unsigned long long>(text.size());
    const unsigned long long limit = std::numeric_limits<std::uint32_t>::max();
    if (*vertices > limit || *faces > limit || *vertices * 2 * unsigned(dimensions) + *faces * 4 > bytes + 16)
        throw InputError(format("{}: the OFF header claims {} vertices and {} faces, more than the file's {} bytes "
                                "can hold",
                                name, *vertices, *faces, bytes));
}

}  // namespace

Polygons readOff(const std::filesystem::path& file, const std::string& name) {
    const std::string text = readTextFile(file);
    checkOffHeader(text, name);
    std::istringstream in(text);
    std::vector<Point> points;
    std::vector<std::vector<std::size_t>> faces;
    bool read = false;
    try {
        read = CGAL::IO::read_OFF(in, points, faces, CGAL::parameters::verbose(false));
    } catch (const std::exception& e) {  // CGAL's assertions, or a failed allocation
        throw InputError(format("{}: not a readable OFF file: {}", name, oneLine(e.what())));
    }
    if (!read) throw InputError(format("{}: not a readable OFF file", name));
    Polygons out;
    out.points.reserve(points.size());
    for (const Point& p : points) out.points.emplace_back(p.x(), p.y(), p.z());
    out.faces.reserve(faces.size());
    for (const std::vector<std::size_t>& face : faces)  // CGAL's reader refuses an index out of range
        out.faces.emplace_back(face.begin(), face.end());
    return out;
}

}  // namespace dawnforge::detail
