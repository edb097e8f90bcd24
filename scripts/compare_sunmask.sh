#!/bin/sh
# Times terracast's shadow against GRASS r.sunmask on one DEM for four suns and judges both masks against an
# independent march towards the sun at 2000 random samples per sun. Not part of CI (GRASS is large):
#   apt-get install grass-core gdal-bin python3-gdal python3-numpy
#   scripts/compare_sunmask.sh [DEM] [TERRACAST]
# The default DEM is the White Mountains tile warped to UTM 19N at 270 m (307 x 421): r.sunmask takes about 17 s
# a sun there and several minutes at 90 m. Matched settings: the sun's azimuth clockwise from grid north for both (r.sunmask's azimuth= takes the same),
# its elevation above the horizontal, flat earth, the whole DEM; -z so that r.sunmask keeps heights of 0.
# r.sunmask runs on one thread (it has no other), terracast on 2. Whole commands are timed.
set -eu
default_res=270
. "$(dirname "$0")/grass_common.sh"
echo "| sun (azimuth, elevation) | r.sunmask s | terracast s | ratio | shadowed: r.sunmask / terracast / reference | agree with the reference: r.sunmask / terracast |"
echo "|---|---|---|---|---|---|"
for sun in "315 20" "135 10" "200 35" "90 5"; do
    set -- $sun
    tg=$(seconds grass "$work/gdb/loc/PERMANENT" --exec sh -c "g.region raster=dem --quiet && r.sunmask -z \
        elevation=dem output=sm altitude=$2 azimuth=$1 --quiet --overwrite")
    tt=$(seconds "$tc" shadow "$dem" --sun "$1,$2" --threads 2 -o "$work/t.tif")
    g r.out.gdal input=sm output="$work/g.tif" format=GTiff type=Byte --quiet --overwrite
    row=$(/usr/bin/python3 - "$work" "$dem" "$1" "$2" <<'PY'
import math, sys
import numpy as np
from osgeo import gdal
work, demPath, az, el = sys.argv[1], sys.argv[2], math.radians(float(sys.argv[3])), math.radians(float(sys.argv[4]))
ds = gdal.Open(demPath)
z = ds.ReadAsArray().astype(np.float64)
nd = ds.GetRasterBand(1).GetNoDataValue()
cell = abs(ds.GetGeoTransform()[1])
H, W = z.shape
valid = np.isfinite(z) if nd is None else (z != nd) & np.isfinite(z)
cv = valid[:-1, :-1] & valid[:-1, 1:] & valid[1:, :-1] & valid[1:, 1:]  # cells with all four corners
t = gdal.Open(f"{work}/t.tif").ReadAsArray()
gds = gdal.Open(f"{work}/g.tif")  # kept alive while its band is read
gband = gds.GetRasterBand(1)
g = gband.ReadAsArray()
gnd = gband.GetNoDataValue()
tShadow = t == 1
gShadow = (g == 1) if gnd is None else (g == 1) & (g != gnd)
# The reference: from the sample towards the sun over the bilinear surface every 1/50 of a sample, shadowed when
# the ground rises 5 cm above the sun's ray somewhere, lit when it stays 5 cm below everywhere (else left out).
rng = np.random.default_rng(3)
verdicts = []
tries = 0
while len(verdicts) < 2000 and tries < 20000:
    tries += 1
    r, c = int(rng.integers(1, H - 1)), int(rng.integers(1, W - 1))
    if not valid[r, c] or t[r, c] > 1:
        continue
    s = np.arange(0.02, 2 * max(H, W), 0.02)
    x, y = c + s * math.sin(az), r - s * math.cos(az)
    inside = (x >= 0) & (y >= 0) & (x <= W - 1) & (y <= H - 1)
    x, y, s = x[inside], y[inside], s[inside]
    i, j = np.minimum(np.floor(x).astype(int), W - 2), np.minimum(np.floor(y).astype(int), H - 2)
    fx, fy = x - i, y - j
    # A point on a grid line (a sun along the rows or columns) has surface when the cell on either side is valid.
    ok = (cv[j, i] | ((fy > 1 - 1e-9) & cv[np.minimum(j + 1, H - 2), i]) | ((fy < 1e-9) & cv[np.maximum(j - 1, 0), i])
          | ((fx > 1 - 1e-9) & cv[j, np.minimum(i + 1, W - 2)]) | ((fx < 1e-9) & cv[j, np.maximum(i - 1, 0)]))
    h = z[j, i] * (1 - fx) * (1 - fy) + z[j, i + 1] * fx * (1 - fy) + z[j + 1, i] * (1 - fx) * fy + z[j + 1, i + 1] * fx * fy
    above = (h - (z[r, c] + s * cell * math.tan(el)))[ok]
    top = above.max() if above.size else -1.0
    if abs(top) < 0.05:
        continue
    verdicts.append((r, c, top > 0))
share = lambda m: 100.0 * m[valid].mean()
ref = np.array([v for _, _, v in verdicts])
agree = lambda m: 100.0 * np.mean([m[r, c] == v for r, c, v in verdicts])
print(f"{share(gShadow):.1f} / {share(tShadow):.1f} / {100 * ref.mean():.1f} % | {agree(gShadow):.1f} / {agree(tShadow):.1f} % |")
PY
)
    echo "| $1, $2 | $tg | $tt | $(echo "$tg / $tt" | bc -l | cut -c1-4) | $row"
done
