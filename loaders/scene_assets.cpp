#include "loaders/scene_assets.h"

#include "loaders/image_io.h"
#include "loaders/input_files.h"

#include "loaders/crs.h"
#include "loaders/loader_support.h"
#include "tracer/core/cancel.h"

#include <gdal_priv.h>
#include <gdal_utils.h>

#include <cmath>

namespace terracast {

using namespace loader_support;

namespace {

std::string where(const SceneDescription& scene, const SourceLocation& at) {
    return fmt::format("{}:{}:{}: ", scene.path, at.line, at.column);
}

// Warps `source` onto the DEM's lattice with GDAL's warper (bilinear), into an in-memory dataset.
GDALDatasetUniquePtr warpOntoDem(const std::string& path, GDALDataset& source, const GeoReference& dem,
                                 int64_t width, int64_t height) {
    // The DEM's samples are the grid's vertices: the target raster has one pixel per vertex, with the DEM's
    // own geotransform.
    const double* gt = dem.geoTransform;
    const double xs[2] = {gt[0], gt[0] + gt[1] * double(width)};
    const double ys[2] = {gt[3], gt[3] + gt[5] * double(height)};
    const std::vector<std::string> args{"-of", "MEM", "-r", "bilinear", "-t_srs", dem.crsWkt, "-te",
                                        fmt::format("{:.17g}", std::min(xs[0], xs[1])),
                                        fmt::format("{:.17g}", std::min(ys[0], ys[1])),
                                        fmt::format("{:.17g}", std::max(xs[0], xs[1])),
                                        fmt::format("{:.17g}", std::max(ys[0], ys[1])),
                                        "-ts", std::to_string(width), std::to_string(height)};
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    GDALWarpAppOptions* options = GDALWarpAppOptionsNew(argv.data(), nullptr);
    GDALDatasetH sourceHandle = GDALDataset::ToHandle(&source);
    int usageError = 0;
    GDALDatasetH out = GDALWarp("", nullptr, 1, &sourceHandle, options, &usageError);
    GDALWarpAppOptionsFree(options);
    if (!out) throw InputError(path + ": could not be resampled onto the DEM's grid: " + firstLine(CPLGetLastErrorMsg()));
    return GDALDatasetUniquePtr(GDALDataset::FromHandle(out));
}

}  // namespace

namespace {

// An RGB raster read as linear RGB, warped onto the DEM's lattice when `dem` and the raster are both
// georeferenced, read at its own size otherwise.
DrapeImage readLinearRgb(const std::string& path, const char* what, const GeoReference& dem, int64_t width,
                         int64_t height) {
    registerGdalDrivers();
    QuietGdalErrors quiet;
    checkInputFile(path, what);
    const ExitOnCancel interruptible;
    GDALDatasetUniquePtr dataset(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
    if (!dataset) throw InputError(path + ": not a raster GDAL can read");
    const int bands = dataset->GetRasterCount();
    if (bands < 1) throw InputError(path + ": raster has no band");
    const bool georeferenced = dem.georeferenced && !dem.crsWkt.empty() && dataset->GetSpatialRef() != nullptr;
    GDALDatasetUniquePtr warped;
    GDALDataset* src = dataset.get();
    if (georeferenced) {
        warped = warpOntoDem(path, *dataset, dem, width, height);
        src = warped.get();
    }
    DrapeImage image;
    image.width = src->GetRasterXSize();
    image.height = src->GetRasterYSize();
    if (image.width < 1 || image.height < 1) throw InputError(path + ": raster is empty");
    const size_t pixels = size_t(image.width) * size_t(image.height);
    image.rgb.assign(pixels * 3, 0.0f);
    std::vector<float> band(pixels);
    // Bytes are sRGB-encoded 0..255; other types are taken as linear 0..1 reflectance.
    const bool bytes = dataset->GetRasterBand(1)->GetRasterDataType() == GDT_Byte;
    for (int c = 0; c < 3; ++c) {
        GDALRasterBand* b = src->GetRasterBand(std::min(c + 1, bands < 3 ? 1 : 3));
        if (b->RasterIO(GF_Read, 0, 0, image.width, image.height, band.data(), image.width, image.height, GDT_Float32,
                        0, 0) != CE_None)
            throw InputError(path + ": could not be read: " + firstLine(CPLGetLastErrorMsg()));
        for (size_t k = 0; k < pixels; ++k)
            image.rgb[k * 3 + size_t(c)] = bytes ? linearFromSrgb(std::clamp(band[k] / 255.0f, 0.0f, 1.0f))
                                                 : std::clamp(band[k], 0.0f, 1.0f);
    }
    return image;
}

}  // namespace

DrapeImage loadDrape(const std::string& path, const GeoReference& dem, int64_t width, int64_t height) {
    return readLinearRgb(path, "a drape image", dem, width, height);
}

EnvironmentImage loadEnvironment(const std::string& path) {
    RgbImage picture = readImage(path);
    for (size_t k = 0; k < picture.rgb.size(); ++k)
        if (!(std::isfinite(picture.rgb[k]) && picture.rgb[k] >= 0.0f)) {
            const size_t pixel = k / 3;
            throw InputError(fmt::format("{}: expected radiances >= 0 in every pixel, found {} at pixel ({}, {})",
                                         path, picture.rgb[k], pixel % size_t(picture.width),
                                         pixel / size_t(picture.width)));
        }
    EnvironmentImage image;
    image.width = picture.width;
    image.height = picture.height;
    image.rgb = std::move(picture.rgb);
    return image;
}

DrapeImage loadTexture(const std::string& path) { return readLinearRgb(path, "a texture image", GeoReference{}, 0, 0); }

LoadedSceneAssets loadSceneAssets(const SceneDescription& scene, double maxBytes) {
    LoadedSceneAssets out;
    for (const ObjectDescription& o : scene.objects) {
        if (o.kind != ObjectKind::HeightField) continue;
        DemLoadOptions options;
        options.imageCellSizeM = o.cellSizeM;
        options.imageHeightScale = o.heightScale;
        options.maxBytes = maxBytes;
        options.exaggeration = o.exaggeration;
        try {
            LoadedDem dem = loadDem(o.filePath, options);
            for (auto& w : dem.warnings) out.warnings.push_back(w);
            out.bytes += double(dem.grid.memoryBytes());
            out.geo.push_back(dem.geo);
            out.assets.grids.push_back(std::make_shared<const HeightGrid>(std::move(dem.grid)));
        } catch (const InputError& e) {
            throw InputError(where(scene, o.fileWhere) + "file: " + e.what());
        } catch (const GridError& e) {
            throw InputError(where(scene, o.fileWhere) + "file: " + e.what());
        }
    }
    for (const MaterialDescription& m : scene.materials) {
        if (m.terrain != TerrainColouring::Drape || m.drapePath.empty()) {
            out.assets.drapes.push_back(nullptr);
            continue;
        }
        if (out.assets.grids.empty())
            throw InputError(where(scene, m.drapeWhere) + "a drape needs a height field in the scene");
        const HeightGrid& grid = *out.assets.grids.front();
        try {
            auto drape = std::make_shared<DrapeImage>(loadDrape(m.drapePath, out.geo.front(), grid.width(), grid.height()));
            out.bytes += double(drape->rgb.size() * sizeof(float));
            out.assets.drapes.push_back(std::move(drape));
        } catch (const InputError& e) {
            throw InputError(where(scene, m.drapeWhere) + "drape: " + e.what());
        }
    }
    if (scene.sky.kind == SkyKind::Image && !scene.sky.imagePath.empty()) {
        try {
            auto environment = std::make_shared<EnvironmentImage>(loadEnvironment(scene.sky.imagePath));
            out.bytes += double(environment->rgb.size() * sizeof(float));
            out.assets.environment = std::move(environment);
        } catch (const InputError& e) {
            throw InputError(where(scene, scene.sky.imageWhere) + "file: " + e.what());
        }
    }
    for (const MaterialDescription& m : scene.materials) {
        if (m.texturePath.empty()) {
            out.assets.textures.push_back(nullptr);
            continue;
        }
        try {
            auto texture = std::make_shared<DrapeImage>(loadTexture(m.texturePath));
            out.bytes += double(texture->rgb.size() * sizeof(float));
            out.assets.textures.push_back(std::move(texture));
        } catch (const InputError& e) {
            throw InputError(where(scene, m.textureWhere) + "texture: " + e.what());
        }
    }
    return out;
}

std::vector<std::string> placeTimedSuns(SceneDescription& scene, const LoadedSceneAssets& loaded) {
    std::vector<std::string> lines;
    for (LightDescription& light : scene.lights) {
        if (light.kind != LightKind::Sun || !light.time) continue;
        if (loaded.assets.grids.empty() || !loaded.geo.front().georeferenced)
            throw InputError(where(scene, light.where) +
                             "time: placing the sun by time needs a georeferenced height field to say where on the "
                             "Earth the scene is (give azimuth and elevation instead)");
        const HeightGrid& grid = *loaded.assets.grids.front();
        try {
            lines.push_back(placeSunOverGrid(*light.time, loaded.geo.front(), grid.width(), grid.height(),
                                             "the first height field", light.azimuthDeg, light.elevationDeg));
        } catch (const InputError& e) {
            const std::string what = e.what();
            throw InputError(where(scene, light.where) + (what.rfind("time:", 0) == 0 ? "" : "time: ") + what);
        }
    }
    return lines;
}

}  // namespace terracast
