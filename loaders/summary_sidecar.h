// The summary of a DEM held as tiles (heightfield/grid_summary.h), kept in a sidecar file beside the DEM, as
// GDAL keeps overviews in a .ovr: opening the DEM again reads the summary instead of streaming every sample
// (docs/architecture.md, "Tiled grids"). The sidecar names what it was made from (every file GDAL reads for the
// raster, with its size and modification time, and how the samples are decoded); a sidecar whose key differs
// (the DEM or a VRT's source changed) or that does not parse is made again.
#pragma once

#include "heightfield/grid_summary.h"
#include "loaders/dem_loader.h"

#include <optional>
#include <string>

namespace terracast {

// The sidecar's path: the DEM's own with ".terracast-summary" appended; for the heights under a vertical
// exaggeration other than 1, ".xFACTOR.terracast-summary".
std::string summarySidecarPath(const std::string& demPath, double exaggeration = 1.0);

// The key a sidecar must carry to describe `reader`'s raster as it is now; empty when the raster has a file
// that is not a local regular file (an in-memory or network source), which gets no sidecar.
std::string summaryKey(const DemWindowReader& reader);

// The summary stored at `sidecarPath` under `key`, for a grid of width x height vertices; nothing when the file
// is missing, carries another key, or does not parse.
std::optional<GridSummary> readSummarySidecar(const std::string& sidecarPath, const std::string& key, int64_t width,
                                              int64_t height);

// Writes `summary` under `key` to `sidecarPath` (through a temporary file and a rename). Returns "" or the reason
// it could not (a read-only folder): the sidecar is a cache, and a DEM opens without it.
std::string writeSummarySidecar(const std::string& sidecarPath, const std::string& key, const GridSummary& summary);

// A level of detail's coarser grid of the DEM (heightfield/coarser_grid.h), `levels` steps coarser, kept beside
// it the same way: ".terracast-lodLEVELS" appended to the DEM's path (after ".xFACTOR" under an exaggeration),
// keyed as the summary is.
std::string coarseSidecarPath(const std::string& demPath, double exaggeration, int levels);
// The coarse grid kept at `sidecarPath` under `key`, when it is `width` x `height` vertices and sound; nothing
// otherwise.
std::optional<CoarseHeights> readCoarseSidecar(const std::string& sidecarPath, const std::string& key, int64_t width,
                                               int64_t height);
// Returns "" or why it could not write.
std::string writeCoarseSidecar(const std::string& sidecarPath, const std::string& key, const CoarseHeights& heights);

}  // namespace terracast
