#include "test_support.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

extern char** environ;

namespace dawnforge::test {

namespace fs = std::filesystem;

TempDir::TempDir() {
    std::string pattern = (fs::temp_directory_path() / "dawnforge-test-XXXXXX").string();
    if (!::mkdtemp(pattern.data())) throw std::runtime_error("mkdtemp failed");
    path_ = pattern;
}

TempDir::~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
}

std::vector<std::string> TempDir::entries() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(path_)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

fs::path dataFile(const std::string& name) { return fs::path(DAWNFORGE_TEST_DATA) / name; }

std::string readText(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

std::vector<unsigned char> readBytes(const fs::path& file) {
    const std::string s = readText(file);
    return {s.begin(), s.end()};
}

void writeText(const fs::path& file, const std::string& text) {
    std::ofstream(file, std::ios::binary) << text;
}

void writeObj(const fs::path& file, const Mesh& mesh) {
    std::ofstream out(file);
    char line[128];
    for (const glm::vec3& p : mesh.positions) {
        std::snprintf(line, sizeof line, "v %.9g %.9g %.9g\n", p.x, p.y, p.z);
        out << line;
    }
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t)
        out << "f " << mesh.indices[3 * t] + 1 << ' ' << mesh.indices[3 * t + 1] + 1 << ' '
            << mesh.indices[3 * t + 2] + 1 << '\n';
}

RunResult run(const std::string& program, const std::vector<std::string>& args) {
    TempDir tmp;
    const std::string outFile = (tmp / "stdout").string(), errFile = (tmp / "stderr").string();
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 1, outFile.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&actions, 2, errFile.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    std::vector<std::string> argvStrings{program};
    argvStrings.insert(argvStrings.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& s : argvStrings) argv.push_back(s.data());
    argv.push_back(nullptr);
    pid_t pid = 0;
    const int spawned = posix_spawn(&pid, program.c_str(), &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (spawned != 0) throw std::runtime_error("cannot start " + program);
    int status = 0;
    ::waitpid(pid, &status, 0);
    RunResult r;
    r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    r.out = readText(outFile);
    r.err = readText(errFile);
    return r;
}

RunResult runDawnforge(const std::vector<std::string>& args) { return run(DAWNFORGE_EXE, args); }

const fs::path& streamWorld() {
    static const fs::path dir = [] {
        const fs::path d = fs::path(DAWNFORGE_TEST_WORK) / "stream-world";
        fs::create_directories(d.parent_path());
        const int fd = ::open((d.string() + ".lock").c_str(), O_CREAT | O_RDWR, 0644);
        if (fd < 0 || ::flock(fd, LOCK_EX) != 0) throw std::runtime_error("cannot lock " + d.string() + ".lock");
        // A world an older executable built is built again: a rerun of `world build` would keep
        // its tiles, and the goldens would show what the old generator made.
        std::error_code ec;
        if (fs::exists(d / "tileset.json", ec) && fs::last_write_time(DAWNFORGE_EXE, ec) > fs::last_write_time(d / "tileset.json", ec))
            fs::remove_all(d, ec);
        const RunResult p = runDawnforge({"-q", "world", "plan", d.string(), "--size", "256x256", "--tile-size", "128", "--seed", "5",
                                          "--bake-texel", "2", "--bake-interior-texel", "4", "--bake-ground-texel", "8",
                                          "--bake-samples", "2", "--bake-sun-samples", "2", "--bake-bounces", "1"});
        const RunResult b = p.exitCode == 0 ? runDawnforge({"-q", "world", "build", d.string(), "--stages", "city,bake,hlod"}) : p;
        ::flock(fd, LOCK_UN);
        ::close(fd);
        if (b.exitCode != 0) throw std::runtime_error("building the test world failed: " + b.err);
        return d;
    }();
    return dir;
}

void expectValidGltf(const fs::path& file) {
    const fs::path validator(DAWNFORGE_GLTF_VALIDATOR);
    if (std::string(DAWNFORGE_NODE).empty())
        GTEST_SKIP() << "node was not found when configuring: " << file.filename() << " was not validated";
    if (!fs::exists(validator.parent_path() / "node_modules/gltf-validator/package.json"))
        GTEST_SKIP() << "the glTF-Validator is not installed (npm ci in " << validator.parent_path() << "): "
                     << file.filename() << " was not validated";
    const RunResult v = run(DAWNFORGE_NODE, {validator.string(), file.string()});
    EXPECT_EQ(v.exitCode, 0) << v.out << v.err;
    EXPECT_NE(v.out.find(": 0 errors"), std::string::npos) << v.out;
}

std::size_t lineCount(const std::string& text) {
    if (text.empty()) return 0;
    std::size_t n = static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
    return text.back() == '\n' ? n : n + 1;
}

double referenceVolume(const Mesh& mesh) {
    long double v = 0;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        const glm::vec3 &a = mesh.positions[mesh.indices[3 * t]], &b = mesh.positions[mesh.indices[3 * t + 1]],
                        &c = mesh.positions[mesh.indices[3 * t + 2]];
        const long double ax = a.x, ay = a.y, az = a.z, bx = b.x, by = b.y, bz = b.z, cx = c.x, cy = c.y, cz = c.z;
        v += ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
    }
    return static_cast<double>(v / 6.0L);
}

Mesh makeTorus(float majorRadius, float minorRadius, int around, int section) {
    Mesh m;
    m.name = "torus";
    const double tau = 6.283185307179586;
    for (int i = 0; i < around; ++i)
        for (int j = 0; j < section; ++j) {
            const double u = tau * i / around, v = tau * j / section;
            const double ring = majorRadius + minorRadius * std::cos(v);
            m.positions.emplace_back(float(ring * std::cos(u)), float(minorRadius * std::sin(v)),
                                     float(ring * std::sin(u)));
        }
    auto at = [&](int i, int j) { return std::uint32_t(((i + around) % around) * section + (j + section) % section); };
    for (int i = 0; i < around; ++i)
        for (int j = 0; j < section; ++j) {
            const std::uint32_t a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
            m.indices.insert(m.indices.end(), {a, c, b, a, d, c});
        }
    return m;
}

Mesh gridBox(int n) {
    Mesh m;
    for (int axis = 0; axis < 3; ++axis)
        for (int side : {-1, 1}) {
            const int u = (axis + 1) % 3, v = (axis + 2) % 3;
            for (int a = 0; a < n; ++a)
                for (int b = 0; b < n; ++b) {
                    auto corner = [&](int da, int db) {
                        glm::vec3 p(0.0f);
                        p[axis] = float(side);
                        p[u] = -1.0f + 2.0f * float(a + da) / float(n);
                        p[v] = -1.0f + 2.0f * float(b + db) / float(n);
                        return p;
                    };
                    std::array<glm::vec3, 4> q{corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)};
                    if (side < 0) std::reverse(q.begin(), q.end());
                    const auto base = std::uint32_t(m.positions.size());
                    m.positions.insert(m.positions.end(), q.begin(), q.end());
                    m.indices.insert(m.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
                }
        }
    return m;
}

double windingNumber(const Mesh& mesh, const glm::dvec3& p) {
    double total = 0.0;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        const glm::dvec3 a = glm::dvec3(mesh.positions[mesh.indices[3 * t]]) - p;
        const glm::dvec3 b = glm::dvec3(mesh.positions[mesh.indices[3 * t + 1]]) - p;
        const glm::dvec3 c = glm::dvec3(mesh.positions[mesh.indices[3 * t + 2]]) - p;
        const double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
        const double det = glm::dot(a, glm::cross(b, c));
        const double div = la * lb * lc + glm::dot(a, b) * lc + glm::dot(b, c) * la + glm::dot(c, a) * lb;
        total += 2.0 * std::atan2(det, div);
    }
    return total / (4.0 * 3.141592653589793);
}

void damage(std::string& s, const std::string& donor, Rng& rng) {
    if (s.empty()) return;
    const std::size_t at = rng.below(s.size());
    switch (rng.below(6)) {
        case 0: s.resize(at); break;
        case 1:
            for (int k = rng.range(1, 8); k > 0; --k) s[rng.below(s.size())] ^= static_cast<char>(rng.range(1, 255));
            break;
        case 2: s.insert(at, s.substr(at, 1 + rng.below(256))); break;
        case 3: s.erase(at, 1 + rng.below(256)); break;
        case 4: {
            const std::size_t from = rng.below(donor.size()), length = 1 + rng.below(std::min<std::size_t>(64, donor.size() - from));
            s.replace(at, rng.below(64), donor.substr(from, length));
            break;
        }
        default: {
            static const char* const kHuge[] = {"4294967295", "2147483648", "99999999999999999999", "1e308", "-1",
                                                "nan", "\xff\xff\xff\xff", "\xff\xff\xff\x7f", "\x00\x00\x80\x7f"};
            std::size_t start = at;
            while (start < s.size() && !std::isdigit(static_cast<unsigned char>(s[start]))) ++start;
            std::size_t end = start;
            while (end < s.size() && std::isdigit(static_cast<unsigned char>(s[end]))) ++end;
            const std::string huge = kHuge[rng.below(std::size(kHuge))];
            if (end > start) s.replace(start, end - start, huge);
            else s.replace(at, std::min<std::size_t>(4, s.size() - at), huge.size() == 4 ? huge : std::string(4, '\xff'));
        }
    }
}


}  // namespace dawnforge::test
