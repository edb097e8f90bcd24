#!/bin/sh
# Renders the pictures at the top of the README with `render`'s default look (solid base, neutral backdrop,
# physical sky, smooth shading), anti-aliased with 4 samples per pixel.
# Usage: scripts/render-readme-pictures.sh [BUILD_DIR]   (default: build)
set -eu
build=${1:-build}
cd "$(dirname "$0")/.."
bin="$build/terracast"
samples=data-samples
"$bin" render "$samples/usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif" -o docs/st-helens.png \
    --size 480x270 --spp 4 --quiet
"$bin" render "$samples/N44W072.srtm3-white-mountains-nh.hgt" -o docs/white-mountains.png \
    --size 480x270 --spp 4 --exaggeration 2 --quiet
"$bin" render "$samples/puget-sound-usgs-1025x1025-16bit-heightmap.png" -o docs/puget-sound.png \
    --cell-size 160 --height-scale 0.1 --size 480x270 --spp 4 --exaggeration 2 --quiet
echo "rendered docs/st-helens.png, docs/white-mountains.png, docs/puget-sound.png"
