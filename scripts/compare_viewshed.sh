#!/bin/sh
# Times terracast's viewshed against gdal_viewshed and GRASS r.viewshed on one DEM from two observers (the DEM's
# centre sample and Mt Washington's summit, each snapped to a sample so that all three stand at the same ground
# height), and judges each tool's verdicts against an independent sight-line march at 400 random samples.
# Not part of CI (GRASS is large):
#   apt-get install grass-core gdal-bin python3-gdal python3-numpy
#   scripts/compare_viewshed.sh [DEM] [TERRACAST]
# Matched settings: observer 1.7 m above the ground, targets on the ground, curvature coefficient 0.85714 (gdal's
# -cc default; r.viewshed -c -r with refraction_coeff 0.14286), the whole DEM. gdal_viewshed and r.viewshed run
# on one thread (they have no other), terracast on 2 (--threads 2). Whole commands are timed; RUNS=N repeats
# gdal_viewshed's and terracast's N times, taking turns, and reports their medians.
set -eu
. "$(dirname "$0")/grass_common.sh"
summit=$(echo "-71.3033 44.2706" | gdaltransform -s_srs EPSG:4326 -t_srs "$dem" -output_xy 2>/dev/null || true)
[ -n "$summit" ] || summit=$(echo "-71.3033 44.2706" | gdaltransform -s_srs EPSG:4326 -t_srs EPSG:32619 | cut -d' ' -f1,2)
# Observers snapped to sample centres.
observers=$(/usr/bin/python3 - "$dem" "$summit" <<'PY'
import sys
from osgeo import gdal
ds = gdal.Open(sys.argv[1])
gt = ds.GetGeoTransform()
W, H = ds.RasterXSize, ds.RasterYSize
sx, sy = map(float, sys.argv[2].split()[:2])
def snap(c, r):
    return f"{gt[0] + (c + 0.5) * gt[1]:.3f},{gt[3] + (r + 0.5) * gt[5]:.3f}"
print(snap(W // 2, H // 2), snap(int((sx - gt[0]) / gt[1]), int((sy - gt[3]) / gt[5])))
PY
)
echo "| observer | gdal_viewshed s | r.viewshed s | terracast s | visible: gdal / GRASS / terracast / reference | agree with the reference: gdal / GRASS / terracast |"
echo "|---|---|---|---|---|---|"
median() { printf '%s\n' "$@" | sort -n | awk '{v[NR] = $1} END {print v[int((NR + 1) / 2)]}'; }
name=valley
for obs in $observers; do
    ox=${obs%,*}
    oy=${obs#*,}
    # gdal_viewshed and terracast take turns RUNS times (1 unless set); the median of each is reported.
    gds="" tcs=""
    for _ in $(seq "${RUNS:-1}"); do
        gds="$gds $(seconds gdal_viewshed -q -oz 1.7 -cc 0.85714 -ox "$ox" -oy "$oy" "$dem" "$work/gd.tif")"
        tcs="$tcs $(seconds "$tc" viewshed "$dem" --observer "$ox,$oy" --observer-height 1.7 --threads 2 -o "$work/tc.tif")"
    done
    tgd=$(median $gds)
    ttc=$(median $tcs)
    tgr=$(seconds grass "$work/gdb/loc/PERMANENT" --exec sh -c "g.region raster=dem --quiet && r.viewshed -b -c -r \
        input=dem output=vs coordinates=$ox,$oy observer_elevation=1.7 refraction_coeff=0.14286 memory=4000 --quiet --overwrite")
    g r.out.gdal input=vs output="$work/gr.tif" format=GTiff type=Byte --quiet --overwrite
    row=$(/usr/bin/python3 - "$work" "$dem" "$ox" "$oy" <<'PY'
import math, sys
import numpy as np
from osgeo import gdal
work, demPath, ox, oy = sys.argv[1], sys.argv[2], float(sys.argv[3]), float(sys.argv[4])
ds = gdal.Open(demPath)
z = ds.ReadAsArray().astype(np.float64)
gt = ds.GetGeoTransform()
nd = ds.GetRasterBand(1).GetNoDataValue()
H, W = z.shape
valid = np.isfinite(z) if nd is None else (z != nd) & np.isfinite(z)
gd = gdal.Open(f"{work}/gd.tif").ReadAsArray() == 255
gr = gdal.Open(f"{work}/gr.tif").ReadAsArray() == 1
tc = gdal.Open(f"{work}/tc.tif").ReadAsArray() == 1
# The reference: the sight line from the eye (1.7 m above the observer's sample) to the target sample, the ground
# under it interpolated bilinearly between samples and lowered with the eye's distance by 0.85714 d^2 / (2 R),
# sampled every 1/50 of a sample; visible when the line clears it everywhere by 5 cm, hidden when it passes 5 cm
# under it somewhere, else grazing and left out.
c0, r0 = (ox - gt[0]) / gt[1] - 0.5, (oy - gt[3]) / gt[5] - 0.5
cell = abs(gt[1])
k = 0.85714 / (2 * 6378137.0)
eye = z[int(round(r0)), int(round(c0))] + 1.7
rng = np.random.default_rng(7)
decided = agree = None
verdicts = []
while len(verdicts) < 400:
    r, c = int(rng.integers(0, H)), int(rng.integers(0, W))
    if not valid[r, c] or (r == round(r0) and c == round(c0)):
        continue
    n = int(50 * math.hypot(r - r0, c - c0)) + 2
    f = np.linspace(0.0, 1.0, n)[1:-1]
    x, y = c0 + f * (c - c0), r0 + f * (r - r0)
    i = np.minimum(np.floor(x).astype(int), W - 2)
    j = np.minimum(np.floor(y).astype(int), H - 2)
    fx, fy = x - i, y - j
    q = [z[j, i], z[j, i + 1], z[j + 1, i], z[j + 1, i + 1]]
    ok = valid[j, i] & valid[j, i + 1] & valid[j + 1, i] & valid[j + 1, i + 1]
    h = q[0] * (1 - fx) * (1 - fy) + q[1] * fx * (1 - fy) + q[2] * (1 - fx) * fy + q[3] * fx * fy
    d = f * math.hypot(r - r0, c - c0) * cell
    D = math.hypot(r - r0, c - c0) * cell
    target = z[r, c] - k * D * D
    line = eye + f * (target - eye)
    clearance = (line - (h - k * d * d))[ok]
    low = clearance.min() if clearance.size else 1.0
    if abs(low) < 0.05:
        continue
    verdicts.append((r, c, low > 0))
share = lambda m: 100.0 * m[valid].mean()
ref = np.array([v for _, _, v in verdicts])
def agreement(m):
    return 100.0 * np.mean([m[r, c] == v for r, c, v in verdicts])
print(f"{share(gd):.1f} / {share(gr):.1f} / {share(tc):.1f} / {100 * ref.mean():.1f} % | "
      f"{agreement(gd):.1f} / {agreement(gr):.1f} / {agreement(tc):.1f} % |")
PY
)
    echo "| $name ($ox, $oy) | $tgd | $tgr | $ttc | $row"
    name=summit
done
