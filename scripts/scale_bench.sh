#!/bin/sh
# Measures what docs/scale.md reports: the cost of holding a DEM as tiles (a cache of an eighth of the grid
# against the whole grid in memory) for a shadow map and a render, and the parallel efficiency of 2 MPI ranks
# against 1 for the same jobs. Not part of CI (minutes of work):
#   scripts/scale_bench.sh [TERRACAST] [SIZE]
# The DEM: the Puget Sound height map resampled to SIZE x SIZE vertices (default 8193), its 16-bit codes mapped
# to 0 to 4392 m (Mount Rainier's height), as a tiled, DEFLATE
# GeoTIFF in UTM metres (30 m cells), made once in a temporary folder. Times are whole processes (load, trace,
# write); ratios are taken between runs made one after the other on the same machine. The DEM's tile store
# (--tile-store, DEM.terracast-tiles) is made beside it in the same temporary folder.
set -eu
here=$(cd "$(dirname "$0")/.." && pwd)
terracast=${1:-$here/build/terracast}
size=${2:-8193}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
dem=$work/dem.tif
extent=$(( (size - 1) * 30 ))
gdal_translate -q -ot Int16 -scale 0 65535 0 4392 -outsize "$size" "$size" -r bilinear -a_srs EPSG:32610 \
  -a_ullr 500000 $((5000000 + extent)) $((500000 + extent)) 5000000 -co TILED=YES -co COMPRESS=DEFLATE \
  "$here/data-samples/puget-sound-usgs-1025x1025-16bit-heightmap.png" "$dem"
# The whole grid's bytes, from `info`, and a cache of an eighth of them.
grid=$("$terracast" info "$dem" | sed -n 's/^memory: *\([0-9.]*\) MiB for the grid.*/\1/p')
[ -n "$grid" ] || grid=$(( size * size * 3 / 1048576 ))
cache=$(awk -v g="$grid" 'BEGIN { printf "%dM", g / 8 }')
echo "grid $size x $size, about $grid MiB in memory; tile cache $cache"

seconds() { # runs a command, prints its wall seconds
    start=$(date +%s.%N)
    "$@" >/dev/null 2>&1
    end=$(date +%s.%N)
    awk -v a="$start" -v b="$end" 'BEGIN { printf "%.2f", b - a }'
}
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.2f", a / b }'; }

for job in "shadow --sun 135,20" "render --size 1920x1080 --sky-samples 0"; do
    name=${job%% *}
    ext=tif
    [ "$name" = render ] && ext=png
    whole=$(seconds "$terracast" $job "$dem" -o "$work/whole.$ext" --threads 2)
    tiled=$(seconds "$terracast" $job "$dem" -o "$work/tiled.$ext" --threads 2 --tile-cache "$cache")
    cmp -s "$work/whole.$ext" "$work/tiled.$ext" && same=identical || same=DIFFERENT
    echo "$name: whole process, grid in memory $whole s, as tiles with a cache of $cache $tiled s: time ratio $(ratio "$whole" "$tiled") (the in-memory run includes reading the whole DEM; the rays' rates are in each summary line); outputs $same"
    # The same from the tile store (--tile-store): the first run fills it, the second reads every tile from it.
    filling=$(seconds "$terracast" $job "$dem" -o "$work/stored.$ext" --threads 2 --tile-cache "$cache" --tile-store)
    stored=$(seconds "$terracast" $job "$dem" -o "$work/stored.$ext" --threads 2 --tile-cache "$cache" --tile-store)
    cmp -s "$work/whole.$ext" "$work/stored.$ext" && same=identical || same=DIFFERENT
    echo "$name: as tiles from the tile store $stored s (the run filling it: $filling s): time ratio $(ratio "$whole" "$stored"); outputs $same"
    one=$(seconds "$terracast" $job "$dem" -o "$work/one.$ext" --threads 1)
    two=$(seconds mpirun --allow-run-as-root --oversubscribe -n 2 "$terracast" $job "$dem" -o "$work/two.$ext" --threads 1)
    cmp -s "$work/one.$ext" "$work/two.$ext" && same=identical || same=DIFFERENT
    echo "$name: 1 rank $one s, 2 ranks $two s: parallel efficiency $(awk -v a="$one" -v b="$two" 'BEGIN { printf "%.2f", a / (2 * b) }'); outputs $same"
done
