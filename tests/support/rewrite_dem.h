// Rewriting a test's copy of a 16-bit DEM in place, as a user's edit would: the same file, new heights.
#pragma once

#include <catch2/catch.hpp>
#include <gdal.h>

#include <cstdint>
#include <string>
#include <vector>

namespace terracast::testing {

// Adds `metres` to every valid height of the Int16 DEM at `path`, through GDAL, in place (the file keeps its size;
// only its times tell it changed).
inline void raiseValidHeights(const std::string& path, int metres) {
    GDALAllRegister();
    GDALDatasetH ds = GDALOpen(path.c_str(), GA_Update);
    REQUIRE(ds != nullptr);
    GDALRasterBandH band = GDALGetRasterBand(ds, 1);
    const int w = GDALGetRasterXSize(ds), h = GDALGetRasterYSize(ds);
    std::vector<int16_t> z(size_t(w) * size_t(h));
    REQUIRE(GDALRasterIO(band, GF_Read, 0, 0, w, h, z.data(), w, h, GDT_Int16, 0, 0) == CE_None);
    const double nodata = GDALGetRasterNoDataValue(band, nullptr);
    for (int16_t& v : z)
        if (double(v) != nodata) v = int16_t(v + metres);
    REQUIRE(GDALRasterIO(band, GF_Write, 0, 0, w, h, z.data(), w, h, GDT_Int16, 0, 0) == CE_None);
    GDALClose(ds);
}

}  // namespace terracast::testing
