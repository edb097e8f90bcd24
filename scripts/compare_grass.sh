#!/bin/sh
# Times terracast's horizon against GRASS r.horizon on one DEM, with matched conventions, and compares their
# values; prints a table row per azimuth. Not part of CI (GRASS is large):
#   apt-get install grass-core gdal-bin python3-gdal python3-numpy
#   scripts/compare_grass.sh [DEM] [TERRACAST]
# DEM defaults to the White Mountains SRTM tile warped to UTM 19N at 90 m (a projected grid, as r.horizon wants);
# TERRACAST to build/terracast.
# Conventions: terracast's azimuth is clockwise from grid north; r.horizon's direction is counter-clockwise from
# east, so direction = (90 - azimuth) mod 360. Both read the whole DEM (r.horizon's default maxdistance) and
# write degrees (r.horizon -d). r.horizon runs on one thread; terracast on all cores (--threads 0).
set -eu
. "$(dirname "$0")/grass_common.sh"
# Agreement of two horizon rasters on the vertices both give: the mean and the spread of terracast - r.horizon,
# and the shares within 0.1 and 1 degree. r.horizon samples the surface a cell apart along the azimuth and
# interpolates it, so it reads peaks between its samples low; terracast's walk is exact on the bilinear surface.
# Vertices where terracast finds no surface that way (-90: nodata to the DEM's edge) are left out. Then both
# against an independent reference at 60 random vertices: a march over the bilinear surface every 1/50 of a cell,
# written here in numpy (a lower bound of the exact horizon, within about 0.01 degree of it).
compare() {
    /usr/bin/python3 - "$1" "$2" "$3" "$4" <<'PY'
import math
import sys
import numpy as np
from osgeo import gdal
t = gdal.Open(sys.argv[1]).ReadAsArray().astype(np.float64)
g = gdal.Open(sys.argv[2]).ReadAsArray().astype(np.float64)
m = (t != -9999) & (t > -89.9) & np.isfinite(g) & (np.abs(g) < 1e30)
d = (t - g)[m]
ds = gdal.Open(sys.argv[3])
z = ds.ReadAsArray().astype(np.float64)
nodata = ds.GetRasterBand(1).GetNoDataValue()
cell = abs(ds.GetGeoTransform()[1])
az = math.radians(float(sys.argv[4]))
H, W = z.shape
rng = np.random.default_rng(1)
errT, errG = [], []
while len(errT) < 60:
    r, c = int(rng.integers(0, H)), int(rng.integers(0, W))
    if not m[r, c]:
        continue
    steps = np.arange(0.02, 3 * max(H, W), 0.02)
    x = c + steps * math.sin(az)
    y = r - steps * math.cos(az)  # rows grow southward
    inside = (x >= 0) & (y >= 0) & (x <= W - 1) & (y <= H - 1)
    x, y, s = x[inside], y[inside], steps[inside]
    i = np.minimum(np.floor(x).astype(int), W - 2)
    j = np.minimum(np.floor(y).astype(int), H - 2)
    fx, fy = x - i, y - j
    c00, c10, c01, c11 = z[j, i], z[j, i + 1], z[j + 1, i], z[j + 1, i + 1]
    ok = (c00 != nodata) & (c10 != nodata) & (c01 != nodata) & (c11 != nodata)
    if not ok.any():
        continue
    h = c00 * (1 - fx) * (1 - fy) + c10 * fx * (1 - fy) + c01 * (1 - fx) * fy + c11 * fx * fy
    ref = math.degrees(math.atan(np.max(((h - z[r, c]) / (s * cell))[ok])))
    errT.append(t[r, c] - ref)
    errG.append(g[r, c] - ref)
errT, errG = np.abs(errT), np.abs(errG)
print(f"{d.mean():+.3f} | {d.std():.3f} | {100 * np.mean(np.abs(d) < 0.1):.1f} % | {100 * np.mean(np.abs(d) < 1):.1f} % | "
      f"{errT.mean():.4f} / {errT.max():.4f} | {errG.mean():.3f} / {errG.max():.3f} |")
PY
}
echo "| azimuth | r.horizon s | terracast s (whole command) | ratio | mean t - g (deg) | sd | within 0.1 | within 1 | terracast - reference, mean / max | r.horizon - reference, mean / max |"
echo "|---|---|---|---|---|---|---|---|---|---|"
for az in 90 315 45 200; do
    dir=$(( (450 - az) % 360 ))
    name=$(printf 'h_%03d' "$dir")
    tg=$(seconds grass "$work/gdb/loc/PERMANENT" --exec sh -c "g.region raster=dem --quiet && r.horizon -d elevation=dem direction=$dir output=h --quiet --overwrite")
    tt=$(seconds "$tc" horizon "$dem" --azimuth "$az" --threads 0 -o "$work/t.tif")
    g r.out.gdal input="$name" output="$work/g.tif" format=GTiff type=Float64 --quiet --overwrite
    echo "| $az | $tg | $tt | $(echo "$tg / $tt" | bc -l | cut -c1-4) | $(compare "$work/t.tif" "$work/g.tif" "$dem" "$az")"
done
