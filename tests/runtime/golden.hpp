#pragma once
// Golden images of the render tests (tests/data/golden/): a test fails when more than 0.5 %
// of pixels differ by more than 8 in a channel, or when the mean difference exceeds 1.0 (the
// actual image is then written to the temp folder). DAWNFORGE_UPDATE_GOLDEN=1 rewrites them.
#include "test_support.hpp"

#include <dawnforge/exporters/image.hpp>

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

namespace dawnforge::test {

inline void expectGolden(const std::string& name, const exporters::Image& image) {
    const auto file = test::dataFile("golden/" + name + ".png");
    if (std::getenv("DAWNFORGE_UPDATE_GOLDEN")) {
        std::filesystem::create_directories(file.parent_path());
        exporters::writePng(image, file);
        GTEST_SKIP() << "rewrote " << file;
    }
    ASSERT_TRUE(std::filesystem::exists(file)) << file << " is missing (DAWNFORGE_UPDATE_GOLDEN=1 makes it)";
    const exporters::Image golden = exporters::readPng(file);
    ASSERT_EQ(golden.width, image.width);
    ASSERT_EQ(golden.height, image.height);
    std::size_t different = 0;
    double sum = 0.0;
    for (std::size_t p = 0; p < image.rgba.size(); p += 4) {
        int worst = 0;
        for (std::size_t c = 0; c < 3; ++c) {
            const int d = std::abs(int(image.rgba[p + c]) - int(golden.rgba[p + c]));
            worst = std::max(worst, d);
            sum += d;
        }
        if (worst > 8) ++different;
    }
    const double pixels = double(image.rgba.size() / 4);
    const double mean = sum / (3.0 * pixels);
    if (double(different) > 0.005 * pixels || mean > 1.0) {
        const auto actual = std::filesystem::temp_directory_path() / ("dawnforge_" + name + ".png");
        exporters::writePng(image, actual);
        ADD_FAILURE() << name << ": " << different << " pixels differ, mean difference " << mean << " (actual image: " << actual
                      << ")";
    }
}

}  // namespace dawnforge::test
