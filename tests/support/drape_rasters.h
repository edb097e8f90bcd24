// Test rasters to drape: written with GDAL, so that loaders and renders read real files.
#pragma once

#include <catch2/catch.hpp>
#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <cstdint>
#include <string>
#include <vector>

namespace terracast::testing {

// Writes a 3-band Byte GeoTIFF: red where x < splitX (in its CRS), blue elsewhere.
inline void writeSplitRaster(const std::string& path, const OGRSpatialReference& srs, double x0, double y0, double dx,
                             double dy, int width, int height, double splitX) {
    GDALAllRegister();
    GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GTiff");
    GDALDatasetUniquePtr ds(driver->Create(path.c_str(), width, height, 3, GDT_Byte, nullptr));
    REQUIRE(ds);
    double gt[6] = {x0, dx, 0.0, y0, 0.0, -dy};
    ds->SetGeoTransform(gt);
    ds->SetSpatialRef(&srs);
    std::vector<uint8_t> band(size_t(width) * size_t(height));
    for (int c = 0; c < 3; ++c) {
        for (int j = 0; j < height; ++j)
            for (int i = 0; i < width; ++i) {
                const bool west = x0 + (i + 0.5) * dx < splitX;
                band[size_t(j) * size_t(width) + size_t(i)] = uint8_t(c == 0 ? (west ? 255 : 0) : c == 2 ? (west ? 0 : 255) : 0);
            }
        REQUIRE(ds->GetRasterBand(c + 1)->RasterIO(GF_Write, 0, 0, width, height, band.data(), width, height, GDT_Byte, 0,
                                                   0) == CE_None);
    }
}

}  // namespace terracast::testing
