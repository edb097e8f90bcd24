#!/bin/sh
# Times terracast's horizon against GRASS r.horizon on one DEM, with matched conventions, and prints a table row
# per azimuth. Not part of CI (GRASS is large): apt-get install grass-core gdal-bin.
#   scripts/compare_grass.sh [DEM] [TERRACAST]
# DEM defaults to the White Mountains SRTM tile warped to UTM 19N at 90 m (a projected grid, as r.horizon wants);
# TERRACAST to build/terracast.
# Conventions: terracast's azimuth is clockwise from grid north; r.horizon's direction is counter-clockwise from
# east, so direction = (90 - azimuth) mod 360. Both read the whole DEM (r.horizon's default maxdistance) and
# write degrees (r.horizon -d). r.horizon runs on one thread; terracast on all cores (--threads 0).
set -eu
here=$(cd "$(dirname "$0")/.." && pwd)
tc=${2:-$here/build/terracast}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
if [ $# -ge 1 ]; then
    dem=$1
else
    dem=$work/white-mountains-utm19n-90m.tif
    gdalwarp -q -t_srs EPSG:32619 -tr 90 90 -r bilinear "$here/data-samples/N44W072.srtm3-white-mountains-nh.hgt" "$dem"
fi
grass -c "$dem" "$work/gdb/loc" -e >/dev/null 2>&1
g() { grass "$work/gdb/loc/PERMANENT" --exec "$@" >/dev/null 2>&1; }
g r.in.gdal input="$dem" output=dem --quiet
seconds() { /usr/bin/time -f %e "$@" 2>&1 >/dev/null | tail -1; }
echo "| azimuth | r.horizon s | terracast s (whole command) | ratio |"
echo "|---|---|---|---|"
for az in 90 315 45 200; do
    dir=$(( (450 - az) % 360 ))
    tg=$(seconds grass "$work/gdb/loc/PERMANENT" --exec sh -c "g.region raster=dem --quiet && r.horizon -d elevation=dem direction=$dir output=h --quiet --overwrite")
    tt=$(seconds "$tc" horizon "$dem" --azimuth "$az" --threads 0 -o "$work/t.tif")
    echo "| $az | $tg | $tt | $(echo "$tg / $tt" | bc -l | cut -c1-4) |"
done
