#!/bin/sh
# The "beyond memory" measurement of docs/scale.md: a 65537 x 65537 grid (4.3 billion vertices, 8.6 GB of
# int16 samples) as a tiled DEFLATE GeoTIFF, then a shadow map and a 3840x2160 render with --max-memory 2G,
# each reporting its time and peak resident memory, and the render again with --lod 1. Not part of CI (about 20 minutes on 2 cores, 1.5 GB of disk).
#   scripts/beyond_memory_bench.sh [TERRACAST] [FOLDER]
# The grid is the 8193^2 Puget Sound grid of scripts/scale_bench.sh repeated 8 x 8 times (each copy overlaps its
# neighbour by one vertex, so the copies meet in cliffs): a VRT of 64 sources, written out by gdal_translate.
# FOLDER (default: a temporary one, removed at the end) keeps the DEM and its summary sidecar between runs.
# Needs GNU time (Debian's `time` package) for the peak memory.
set -eu
here=$(cd "$(dirname "$0")/.." && pwd)
terracast=${1:-$here/build/terracast}
work=${2:-}
if [ -z "$work" ]; then
    work=$(mktemp -d)
    trap 'rm -rf "$work"' EXIT
fi
mkdir -p "$work"
small=$work/dem8193.tif
dem=$work/dem65537.tif
if [ ! -f "$dem" ]; then
    gdal_translate -q -ot Int16 -scale 0 65535 0 4392 -outsize 8193 8193 -r bilinear -a_srs EPSG:32610 \
      -a_ullr 500000 5245760 745760 5000000 -co TILED=YES -co COMPRESS=DEFLATE \
      "$here/data-samples/puget-sound-usgs-1025x1025-16bit-heightmap.png" "$small"
    {
        echo '<VRTDataset rasterXSize="65537" rasterYSize="65537">'
        echo '  <SRS>EPSG:32610</SRS>'
        echo '  <GeoTransform>500000, 30, 0, 6966080, 0, -30</GeoTransform>'
        echo '  <VRTRasterBand dataType="Int16" band="1">'
        for j in 0 1 2 3 4 5 6 7; do
            for i in 0 1 2 3 4 5 6 7; do
                echo "    <SimpleSource><SourceFilename>$small</SourceFilename><SourceBand>1</SourceBand>"
                echo "      <SrcRect xOff=\"0\" yOff=\"0\" xSize=\"8193\" ySize=\"8193\"/>"
                echo "      <DstRect xOff=\"$((i * 8192))\" yOff=\"$((j * 8192))\" xSize=\"8193\" ySize=\"8193\"/></SimpleSource>"
            done
        done
        echo '  </VRTRasterBand>'
        echo '</VRTDataset>'
    } > "$work/mosaic.vrt"
    gdal_translate -q --config GDAL_CACHEMAX 512 -co TILED=YES -co COMPRESS=DEFLATE -co PREDICTOR=2 -co ZLEVEL=1 \
      -co BIGTIFF=YES -co NUM_THREADS=ALL_CPUS "$work/mosaic.vrt" "$dem"
fi
measure() { # runs a command under /usr/bin/time; prints its summary line, wall time and peak memory
    /usr/bin/time -f "wall %e s, peak resident %M KiB" "$@" 2>"$work/log" >"$work/out" || { cat "$work/log"; exit 1; }
    grep -hE "^(held|summary):|^terracast: (rendered|shadow)|^wall" "$work/out" "$work/log"
}
measure "$terracast" info "$dem" --max-memory 2G
measure "$terracast" render "$dem" -o "$work/render.png" --size 3840x2160 --max-memory 2G
# The level of detail: the first run makes the coarser grid that fits in the tile cache from every tile and keeps it
# beside the DEM (DEM.terracast-lodL); the second takes it from there.
rm -f "$dem".terracast-lod*
measure "$terracast" render "$dem" -o "$work/render-lod.png" --size 3840x2160 --max-memory 2G --lod 1
measure "$terracast" render "$dem" -o "$work/render-lod.png" --size 3840x2160 --max-memory 2G --lod 1
measure "$terracast" shadow "$dem" --sun 135,20 -o "$work/shadow.tif" --max-memory 2G
