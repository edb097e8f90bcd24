// PNG height maps for tests, written with GDAL's PNG driver: a real encoder, independent of the loaders'.
#pragma once

#include <catch2/catch.hpp>
#include <gdal_priv.h>

#include <string>
#include <vector>

namespace terracast::testing {

// A PNG of `bands` bands of row-major samples (`type` GDT_Byte or GDT_UInt16), band b holding the samples plus
// b - 1 (so that channel 0 is told apart from the others), with the driver's creation options (NBITS=4 for
// 4-bit grey, for one).
inline void writePng(const std::string& path, int width, int height, int bands, GDALDataType type,
                     const std::vector<double>& samples, const std::vector<std::string>& creationOptions = {}) {
    GDALAllRegister();
    GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
    GDALDriver* png = GetGDALDriverManager()->GetDriverByName("PNG");
    REQUIRE(mem != nullptr);
    REQUIRE(png != nullptr);
    REQUIRE(samples.size() == size_t(width) * size_t(height));
    GDALDatasetUniquePtr source(mem->Create("", width, height, bands, type, nullptr));
    REQUIRE(source);
    for (int b = 1; b <= bands; ++b) {
        std::vector<double> values(samples);
        for (double& v : values) v += b - 1;
        REQUIRE(source->GetRasterBand(b)->RasterIO(GF_Write, 0, 0, width, height, values.data(), width, height,
                                                   GDT_Float64, 0, 0, nullptr) == CE_None);
    }
    std::vector<const char*> options;
    for (const std::string& o : creationOptions) options.push_back(o.c_str());
    options.push_back(nullptr);
    GDALDatasetUniquePtr out(png->CreateCopy(path.c_str(), source.get(), FALSE, const_cast<char**>(options.data()),
                                             nullptr, nullptr));
    REQUIRE(out);
}

}  // namespace terracast::testing
