// Readers in a child process (core/isolate.hpp): what a reader does there (crash, hang,
// allocate without end, write files, open sockets, lie about its answer) ends as one line
// naming the file, and a good answer arrives whole.
#include "test_support.hpp"

#include <dawnforge/core/import.hpp>
#include <dawnforge/core/isolate.hpp>
#include <dawnforge/core/primitives.hpp>
#include <dawnforge/core/scene.hpp>
#include <dawnforge/exporters/gltf.hpp>

#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <vector>

namespace dawnforge {
namespace {

namespace fs = std::filesystem;
using test::TempDir;

Answer answerOf(std::string bytes) {
    auto shared = std::make_shared<std::string>(std::move(bytes));
    return {shared->size(), [shared](AnswerSink& sink) { sink.write(shared->data(), shared->size()); }};
}

// Runs `produce` isolated and returns its answer as text.
std::string isolated(const std::function<Answer()>& produce) {
    std::string text;
    readIsolated("input.bin", "TEST", produce, [&](AnswerSource& source) {
        text.resize(source.left());
        source.read(text.data(), text.size());
    });
    return text;
}

// The ReaderFailure that `produce` ends in; fails the test if there is none.
ReaderFailure failureOf(const std::function<Answer()>& produce) {
    try {
        isolated(produce);
    } catch (const ReaderFailure& e) {
        return e;
    } catch (const std::exception& e) {
        ADD_FAILURE() << "not a ReaderFailure: " << e.what();
    }
    ADD_FAILURE() << "no ReaderFailure";
    return {ReaderFailure::Kind::NoAnswer, ""};
}

TEST(Isolate, AnAnswerOfManyMegabytesArrivesWhole) {
    std::string big(5'000'017, '\0');
    for (std::size_t i = 0; i < big.size(); ++i) big[i] = char(i * 2654435761u >> 13);
    EXPECT_EQ(isolated([&] { return answerOf(big); }), big);
    EXPECT_EQ(isolated([] { return answerOf(""); }), "");
}

TEST(Isolate, ACrashIsOneLineNamingTheFileTheReaderAndTheSignal) {
    const ReaderFailure f = failureOf([]() -> Answer {
        std::raise(SIGSEGV);
        return {};
    });
    EXPECT_EQ(f.kind(), ReaderFailure::Kind::Crashed);
    const std::string what = f.what();
    // Under AddressSanitizer its own handler reports the SIGSEGV, then aborts.
    EXPECT_TRUE(what.starts_with("input.bin: the TEST reader crashed (signal ")) << what;
    EXPECT_TRUE(what.find(DAWNFORGE_SANITIZED ? "SIGABRT" : "signal 11, SIGSEGV") != std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos);
}

TEST(Isolate, AReaderThatHangsIsStoppedAtTheTimeLimit) {
    const test::ScopedReaderLimits limits({.seconds = 1.0});
    for (const bool sleeping : {true, false}) {
        const auto start = std::chrono::steady_clock::now();
        const ReaderFailure f = failureOf([sleeping]() -> Answer {
            volatile unsigned long spin = 0;  // busy, and not optimised away
            for (;;) {
                const unsigned long next = spin + 1;
                spin = next;
                if (sleeping) ::pause();
            }
        });
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        EXPECT_EQ(f.kind(), ReaderFailure::Kind::TimedOut) << f.what();
        EXPECT_STREQ(f.what(), "input.bin: the TEST reader gave up after 1 s (--read-timeout)");
        EXPECT_GE(seconds, 0.9);
        EXPECT_LT(seconds, 10.0);
    }
}

// A reader that closes its end of the pipe and lingers is still stopped at the time limit: the
// parent waits for its exit no longer than for its answer.
TEST(Isolate, AReaderThatLingersAfterThePipeIsStoppedAtTheTimeLimit) {
    const test::ScopedReaderLimits limits({.seconds = 1.0});
    const ReaderFailure f = failureOf([]() -> Answer {
        ::close(3);
        for (;;) ::pause();
    });
    EXPECT_EQ(f.kind(), ReaderFailure::Kind::TimedOut) << f.what();
    EXPECT_STREQ(f.what(), "input.bin: the TEST reader gave up after 1 s (--read-timeout)");
}

TEST(Isolate, AReaderThatWantsTooMuchMemoryIsStopped) {
    const test::ScopedReaderLimits limits({.seconds = 30.0, .gigabytes = 0.25});
    // An answer announced larger than the limit is refused before anything is read.
    ReaderFailure f = failureOf([] { return Answer{std::uint64_t(1) << 40, [](AnswerSink&) {}}; });
    EXPECT_EQ(f.kind(), ReaderFailure::Kind::OutOfMemory);
    EXPECT_STREQ(f.what(), "input.bin: the TEST reader needed more than 0.25 GB (--read-memory)");
    f = failureOf([] {
        std::vector<std::vector<char>> blocks;
        for (int i = 0; i < 64; ++i) blocks.emplace_back(std::size_t(64) << 20, char(i));  // 4 GB in all
        return answerOf(std::to_string(blocks.size()));
    });
    // AddressSanitizer's allocator reports the refused mapping itself, then aborts.
    EXPECT_EQ(f.kind(), DAWNFORGE_SANITIZED ? ReaderFailure::Kind::Crashed : ReaderFailure::Kind::OutOfMemory) << f.what();
}

TEST(Isolate, AReadersOwnErrorComesBackAsItsInputError) {
    try {
        isolated([]() -> Answer { throw InputError("input.bin: line 3: 'x' is not a number"); });
        ADD_FAILURE() << "no error";
    } catch (const ReaderFailure& e) {
        ADD_FAILURE() << "a ReaderFailure: " << e.what();
    } catch (const InputError& e) {
        EXPECT_STREQ(e.what(), "input.bin: line 3: 'x' is not a number");
    }
}

TEST(Isolate, TheReaderCannotWriteFilesConnectOrStartPrograms) {
    TempDir dir;
    const fs::path target = dir / "written.txt";
    const std::string report = isolated([&] {
        std::string r;
        r += ::open(target.c_str(), O_WRONLY | O_CREAT, 0644) < 0 && errno == EPERM ? "open-write refused;" : "open-write allowed;";
        r += ::open("/etc/hostname", O_RDONLY) >= 0 || errno != EPERM ? "read allowed;" : "read refused;";
        r += ::socket(AF_INET, SOCK_STREAM, 0) < 0 ? "socket refused;" : "socket allowed;";
        char* const argv[] = {const_cast<char*>("/bin/true"), nullptr};
        r += ::execv("/bin/true", argv) < 0 ? "exec refused;" : "exec allowed;";
        r += ::unlink(dir.path().c_str()) < 0 ? "unlink refused" : "unlink allowed";
        return answerOf(r);
    });
    EXPECT_EQ(report, "open-write refused;read allowed;socket refused;exec refused;unlink refused");
    EXPECT_FALSE(fs::exists(target));
}

TEST(Isolate, AnAnswerShorterOrLongerThanAnnouncedIsRefused) {
    // Cut short: the child ends before its bytes do.
    ReaderFailure f = failureOf([] { return Answer{100, [](AnswerSink& s) { s.write("half", 4); }}; });
    EXPECT_EQ(f.kind(), ReaderFailure::Kind::NoAnswer);
    EXPECT_STREQ(f.what(), "input.bin: the TEST reader ended without an answer (exit 0)");
    // A reader of the answer that wants more than was announced.
    const std::string error = test::inputErrorOf([] {
        readIsolated("input.bin", "TEST", [] { return answerOf("four"); }, [](AnswerSource& source) {
            char bytes[8];
            source.read(bytes, sizeof bytes);
        });
    });
    EXPECT_EQ(error, "input.bin: the reader's answer is damaged (8 bytes wanted, 4 left)");
}

// A GLB with a hierarchy, every attribute the import keeps, and an OBJ: read in a child and in
// this process, the meshes are the same, value for value.
TEST(Isolate, MeshesReadInAChildAreTheSameAsReadHere) {
    TempDir dir;
    Scene scene;
    Mesh sphere = makeIcosphere(1.0f, 2);
    sphere.uv0.assign(sphere.vertexCount(), glm::vec2(0.25f, 0.5f));
    sphere.materialIds.assign(sphere.vertexCount(), 7);
    sphere.pieceIds.assign(sphere.vertexCount(), 3);
    const std::uint32_t parent = scene.addMeshNode(sphere, {1.0f, 2.0f, 3.0f});
    scene.meshes.push_back(makeBox({0, 0, 0}, {1, 2, 1}, 3));
    Node child;
    child.name = "child";
    child.mesh = 1;
    child.translation = {0.0f, 5.0f, 0.0f};
    scene.nodes.push_back(child);
    scene.nodes[parent].children.push_back(std::uint32_t(scene.nodes.size() - 1));
    exporters::writeGlb(scene, dir / "scene.glb");
    test::writeObj(dir / "box.obj", makeBox({0, 0, 0}, {1, 1, 1}, 0));
    for (const fs::path& file : {dir / "scene.glb", dir / "box.obj", test::dataFile("box_zup_cm.fbx")}) {
        const std::vector<MeshNode> a = loadMeshNodes(file, ReadIn::child), b = loadMeshNodes(file, ReadIn::thisProcess);
        ASSERT_EQ(a.size(), b.size()) << file;
        for (std::size_t i = 0; i < a.size(); ++i) {
            EXPECT_EQ(a[i].name, b[i].name);
            EXPECT_EQ(a[i].world, b[i].world);
            EXPECT_EQ(a[i].parent, b[i].parent);
            EXPECT_EQ(a[i].mesh.positions, b[i].mesh.positions);
            EXPECT_EQ(a[i].mesh.indices, b[i].mesh.indices);
            EXPECT_EQ(a[i].mesh.normals, b[i].mesh.normals);
            EXPECT_EQ(a[i].mesh.uv0, b[i].mesh.uv0);
            EXPECT_EQ(a[i].mesh.materialIds, b[i].mesh.materialIds);
            EXPECT_EQ(a[i].mesh.pieceIds, b[i].mesh.pieceIds);
        }
        const Mesh m = loadMesh(file, ReadIn::child), n = loadMesh(file, ReadIn::thisProcess);
        EXPECT_EQ(m.name, n.name);
        EXPECT_EQ(m.positions, n.positions) << file;
        EXPECT_EQ(m.indices, n.indices) << file;
    }
    EXPECT_EQ(loadMeshNodes(dir / "scene.glb").size(), 2u);
}

// The three files that crashed, corrupted the heap of, or hung `dawnforge inspect` when Assimp
// ran in its process (tests/data/hostile/README.md).
TEST(Isolate, TheHostileReproducersEndAsOneLineEach) {
    const test::ScopedReaderLimits limits({.seconds = 3.0});
    const struct {
        const char* file;
        ReaderFailure::Kind kind;
        const char* says;
    } cases[] = {{"hostile/segfault_binary.ply", ReaderFailure::Kind::Crashed, "the PLY reader crashed (signal "},
                 {"hostile/heap_corruption.fbx", ReaderFailure::Kind::Crashed, "the FBX reader crashed (signal "},
                 {"hostile/hang_ascii.ply", ReaderFailure::Kind::TimedOut, "the PLY reader gave up after 3 s"}};
    for (const auto& c : cases) {
        const fs::path file = test::dataFile(c.file);
        try {
            loadMesh(file);
            ADD_FAILURE() << c.file << " loaded";
        } catch (const ReaderFailure& e) {
            EXPECT_EQ(e.kind(), c.kind) << e.what();
            EXPECT_TRUE(std::string(e.what()).starts_with(file.string() + ": " + c.says)) << e.what();
            EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
        } catch (const std::exception& e) {
            ADD_FAILURE() << c.file << ": " << e.what();
        }
    }
}

}  // namespace
}  // namespace dawnforge
