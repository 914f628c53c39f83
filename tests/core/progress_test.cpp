#include <dawnforge/core/progress.hpp>

#include <gtest/gtest.h>

using namespace dawnforge;

TEST(Progress, DisabledPrintsNothing) {
    testing::internal::CaptureStderr();
    {
        StderrProgress progress("work", false);
        ProgressFn fn = progress.callback();
        EXPECT_TRUE(fn(0.5));
        EXPECT_TRUE(fn(1.0));
    }
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
}

TEST(Progress, EnabledPrintsPercentagesAndDone) {
    testing::internal::CaptureStderr();
    {
        StderrProgress progress("fracture", true);
        EXPECT_TRUE(progress(0.0));
        EXPECT_TRUE(progress(1.0));  // the end is always printed, however soon it comes
    }
    const std::string err = testing::internal::GetCapturedStderr();
    EXPECT_NE(err.find("fracture:   0%"), std::string::npos) << err;
    EXPECT_NE(err.find("fracture: 100%"), std::string::npos) << err;
    EXPECT_NE(err.find("fracture: done\033[K\n"), std::string::npos) << err;
    EXPECT_TRUE(noProgress(0.3));
}
