// PNG height maps, read whole: by libspng row by row into int16 codes, or through the image codec module
// (OpenImageIO) for the layouts libspng is not used for. Internal to the loaders: loadDem chooses this reader for a
// .png.
#pragma once

#include "loaders/dem_loader.h"

#include <string>

namespace terracast {

// Loads channel 0 of an 8- or 16-bit PNG height map: options.imageCellSizeM metres between samples and
// options.imageHeightScale metres per stored unit. Throws InputError as loadDem does.
LoadedDem loadPngHeightMap(const std::string& path, const DemLoadOptions& options);

}  // namespace terracast
