// Golden-image comparison: a rendered film against a committed PNG, in the 8-bit sRGB levels it is stored in.
// scripts/update_golden.sh rewrites the references: it runs the golden tests with TERRACAST_UPDATE_GOLDEN=1, and
// each then writes its reference and fails, so an update is never a passing test run.
#pragma once

#include "loaders/image_io.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <unistd.h>

namespace terracast::testing {

// Mean absolute difference under `meanLevels` and at most `offShare` of the samples off by more than 8 levels:
// a changed pixel here and there from compiler rounding is fine; a changed picture is not.
inline void checkGolden(const RgbImage& image, const std::string& golden, double meanLevels = 0.5,
                        double offShare = 0.005) {
    if (std::getenv("TERRACAST_UPDATE_GOLDEN")) {
        writeImage(golden, image);
        FAIL("rewrote " << golden << " (TERRACAST_UPDATE_GOLDEN is set); run the tests without it to check it");
    }
    const std::string tmp = (std::filesystem::temp_directory_path() /
                             ("terracast-golden-" + std::to_string(::getpid()) + ".png")).string();
    writeImage(tmp, image);
    const RgbImage now = readImage(tmp), ref = readImage(golden);
    std::filesystem::remove(tmp);
    REQUIRE(now.width == ref.width);
    REQUIRE(now.height == ref.height);
    auto toLevel = [](float linear) {
        const float c = std::clamp(linear, 0.0f, 1.0f);
        const float s = c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
        return 255.0f * s;
    };
    double sum = 0.0;
    size_t off = 0;
    for (size_t k = 0; k < now.rgb.size(); ++k) {
        const double d = std::abs(toLevel(now.rgb[k]) - toLevel(ref.rgb[k]));
        sum += d;
        off += d > 8.0;
    }
    const double mean = sum / double(now.rgb.size());
    INFO(golden << ": mean difference " << mean << " levels, " << off << " samples off by more than 8 levels");
    CHECK(mean < meanLevels);
    CHECK(double(off) <= offShare * double(now.rgb.size()));
}

}  // namespace terracast::testing
