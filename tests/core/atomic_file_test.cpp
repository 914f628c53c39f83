#include "test_support.hpp"

#include <dawnforge/core/atomic_file.hpp>
#include <dawnforge/core/error.hpp>

#include <gtest/gtest.h>

using namespace dawnforge;
using dawnforge::test::TempDir;

TEST(AtomicFile, CommitWritesTheFileAndLeavesNothingElse) {
    TempDir dir;
    writeFileAtomically(dir / "out.txt", std::string_view("hello"));
    EXPECT_EQ(test::readText(dir / "out.txt"), "hello");
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"out.txt"});
}

TEST(AtomicFile, AbandonedWriteLeavesNoFile) {
    TempDir dir;
    {
        AtomicFile file(dir / "out.bin");
        file.stream() << "partial";
        EXPECT_EQ(dir.entries().size(), 1u);  // the temporary file, not the target
        EXPECT_FALSE(std::filesystem::exists(dir / "out.bin"));
    }
    EXPECT_TRUE(dir.entries().empty());
}

TEST(AtomicFile, OldContentStaysUntilCommit) {
    TempDir dir;
    test::writeText(dir / "out.txt", "old");
    {
        AtomicFile file(dir / "out.txt");
        file.stream() << "new";
        EXPECT_EQ(test::readText(dir / "out.txt"), "old");
        file.commit();
    }
    EXPECT_EQ(test::readText(dir / "out.txt"), "new");
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"out.txt"});
}

TEST(AtomicFile, UnwritablePlacesAreInputErrors) {
    TempDir dir;
    EXPECT_THROW(writeFileAtomically(dir / "missing" / "out.txt", std::string_view("x")), InputError);
    std::filesystem::create_directory(dir / "folder");
    EXPECT_THROW(writeFileAtomically(dir / "folder", std::string_view("x")), InputError);
    test::writeText(dir / "file", "x");
    EXPECT_THROW(ensureOutputDirectory(dir / "file"), InputError);
    EXPECT_NO_THROW(ensureOutputDirectory(dir / "a" / "b"));
    EXPECT_TRUE(std::filesystem::is_directory(dir / "a" / "b"));
}
