#!/bin/sh
# Times terracast's insolation against GRASS r.sun (mode 2: a day's irradiation with terrain shadows) on one DEM
# and compares their bands; prints a table row. Not part of CI (GRASS is large):
#   apt-get install grass-core gdal-bin python3-gdal python3-numpy
#   scripts/compare_rsun.sh [DEM] [TERRACAST]
# DEM defaults to the White Mountains SRTM tile warped to UTM 19N at 90 m; TERRACAST to build/terracast.
# Matched settings: 2026-06-21 (day 172), a 30-minute step, Linke turbidity 3, albedo 0.2, the whole DEM as the
# shadow search. r.sun takes slope and aspect from r.slope.aspect (Horn's 3 x 3 window, aspect counter-clockwise
# from east) and places the sun per cell in local solar time; terracast takes the vertex normal of the bilinear
# surface and places the sun over the DEM's centre in UTC. Both run on 2 threads (r.sun nprocs=2).
set -eu
. "$(dirname "$0")/grass_common.sh"
tg=$(seconds grass "$work/gdb/loc/PERMANENT" --exec sh -c "g.region raster=dem --quiet &&
    r.slope.aspect elevation=dem slope=slope aspect=aspect --quiet --overwrite &&
    r.sun elevation=dem slope=slope aspect=aspect day=172 step=0.5 linke_value=3.0 albedo_value=0.2 nprocs=2 \
      beam_rad=beam diff_rad=diff refl_rad=refl glob_rad=glob insol_time=hours --quiet --overwrite")
tt=$(seconds "$tc" insolation "$dem" --date 2026-06-21 --step 30m --threads 2 -o "$work/t.tif")
for b in beam diff refl glob hours; do
    g r.out.gdal input=$b output="$work/g_$b.tif" format=GTiff type=Float64 --quiet --overwrite
done
/usr/bin/python3 - "$work" "$tg" "$tt" <<'PY'
import sys
import numpy as np
from osgeo import gdal
work, tg, tt = sys.argv[1], float(sys.argv[2]), float(sys.argv[3])
t = gdal.Open(f"{work}/t.tif")
rows = []
# r.slope.aspect leaves the outermost cells null; compare where both have values.
for k, name, label in [(1, "beam", "beam"), (2, "diff", "diffuse"), (3, "refl", "reflected"), (4, "glob", "global"), (5, "hours", "sunshine h")]:
    tv = t.GetRasterBand(k).ReadAsArray().astype(float)
    gd = gdal.Open(f"{work}/g_{name}.tif")
    gv = gd.GetRasterBand(1).ReadAsArray().astype(float)
    nd = gd.GetRasterBand(1).GetNoDataValue()
    ok = (tv > -9999) & np.isfinite(gv)
    if nd is not None:
        ok &= gv != nd
    d = tv[ok] - gv[ok]
    rel = np.abs(d) / np.maximum(np.abs(gv[ok]), 1e-9)
    rows.append(f"| {label} | {gv[ok].mean():.1f} | {tv[ok].mean():.1f} | {d.mean():+.1f} | {np.abs(d).mean():.1f} | "
                f"{100 * (rel <= 0.02).mean():.1f} % | {100 * (rel <= 0.10).mean():.1f} % |")
print(f"r.sun {tg:.1f} s, terracast {tt:.2f} s (whole commands), ratio {tg / tt:.1f}")
print("| band | r.sun mean | terracast mean | mean t - g | mean abs | within 2 % | within 10 % |")
print("|---|---|---|---|---|---|---|")
print("\n".join(rows))
PY
