"""The Python module's benchmarks, in one run on one machine:

1. The cost of the Python call: HeightField.intersect on 10^6 rays, against the loop over the rays inside it,
   timed in C++ (terracast._core._last_loop_seconds): what the call takes beyond tracing (converting the
   arguments, making the result arrays, starting the work, returning) over what tracing takes. Median of 5.
2. Sight lines, exact against what a Python user would write today: a NumPy-vectorised march along each line at
   half-cell steps over the bilinear terrain, on the same 10^5 lines from a tower to points on the ground:
   lines per second and the share of lines where the march disagrees with the exact answer.

    PYTHONPATH=build/python python3 bench/python_bench.py [DEM]
"""

import sys
import time

import numpy as np
from osgeo import gdal

import terracast
from terracast import _core

gdal.UseExceptions()
dem = sys.argv[1] if len(sys.argv) > 1 else "data-samples/usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif"
hf = terracast.HeightField.open(dem)
cx, cy = hf.cell_size
width_m, height_m = (hf.width - 1) * cx, (hf.height - 1) * cy
rng = np.random.default_rng(7)

# 1. The call's overhead: camera-like rays from above the DEM, down at random angles.
n = 1_000_000
origins = np.column_stack([rng.uniform(0, width_m, n), rng.uniform(0, height_m, n),
                           rng.uniform(hf.max_height + 100, hf.max_height + 1500, n)])
directions = np.column_stack([rng.normal(size=n), rng.normal(size=n), -np.abs(rng.normal(size=n)) - 0.3])
overheads, python_s, native_s = [], [], []
for _ in range(5):
    start = time.perf_counter()
    hf.intersect(origins, directions)
    python = time.perf_counter() - start
    native = _core._last_loop_seconds()
    native_s.append(native)
    python_s.append(python)
    overheads.append(python / native - 1.0)
print(f"intersect, {n} rays on {hf.width} x {hf.height}: Python call {np.median(python_s) * 1e3:.1f} ms, "
      f"tracing in it {np.median(native_s) * 1e3:.1f} ms; overhead {100 * np.median(overheads):+.1f} % "
      f"(median of 5 calls; range {100 * min(overheads):+.1f} to {100 * max(overheads):+.1f} %)")

# 2. Sight lines from a tower's top to points 1.7 m above the ground.
dataset = gdal.Open(dem)  # kept: a band outliving its dataset is invalid
band = dataset.GetRasterBand(1)
raster = band.ReadAsArray().astype(np.float64)
nodata = band.GetNoDataValue()
if nodata is not None:
    raster[raster == nodata] = -np.inf  # no terrain: blocks nothing
grid = raster[::-1]  # row j = j cells north of the south edge, as local y


def terrain(x, y):
    """Bilinear height at local (x, y) arrays (inside the grid)."""
    fx, fy = np.clip(x / cx, 0, hf.width - 1.000001), np.clip(y / cy, 0, hf.height - 1.000001)
    i, j = fx.astype(np.int64), fy.astype(np.int64)
    u, v = fx - i, fy - j
    h00, h10, h01, h11 = grid[j, i], grid[j, i + 1], grid[j + 1, i], grid[j + 1, i + 1]
    return (1 - u) * (1 - v) * h00 + u * (1 - v) * h10 + (1 - u) * v * h01 + u * v * h11


def marched(a, b, step_m):
    """Blocked when a sample every step_m (horizontally) along a -> b lies below the terrain."""
    out = np.zeros(len(b), dtype=bool)
    length = np.hypot(b[:, 0] - a[0], b[:, 1] - a[1])
    for s in range(0, len(b), 4096):
        e = min(len(b), s + 4096)
        steps = np.maximum(1, np.ceil(length[s:e] / step_m)).astype(np.int64)
        k = np.arange(1, steps.max())
        f = k[None, :] / steps[:, None]  # fractions along each line; past its end: masked
        inside = f < 1.0
        f = np.where(inside, f, 0.0)
        px = a[0] + f * (b[s:e, 0:1] - a[0])
        py = a[1] + f * (b[s:e, 1:2] - a[1])
        pz = a[2] + f * (b[s:e, 2:3] - a[2])
        out[s:e] = (inside & (pz < terrain(px, py))).any(axis=1)
    return out


def ground(xy):
    down = hf.intersect(np.column_stack([xy, np.full(len(xy), hf.max_height + 100.0)]),
                        np.tile([0.0, 0.0, -1.0], (len(xy), 1)))
    return down["point"][:, 2], down["hit"]


tz, _ = ground(np.array([[0.40 * width_m, 0.30 * height_m]]))
top = np.array([0.40 * width_m, 0.30 * height_m, tz[0] + 60.0])
m = 100_000
xy = np.column_stack([rng.uniform(0, width_m, m), rng.uniform(0, height_m, m)])
z, land = ground(xy)
points = np.column_stack([xy, z + 1.7])[land]
start = time.perf_counter()
exact = hf.occluded(np.broadcast_to(top, points.shape), points - top, t_max=1.0)
exact_s = time.perf_counter() - start
start = time.perf_counter()
march = marched(top, points, 0.5 * min(cx, cy))
march_s = time.perf_counter() - start
print(f"sight lines, {len(points)} from a tower: exact {len(points) / exact_s / 1e6:.3f} M/s, NumPy half-cell "
      f"march {len(points) / march_s / 1e6:.4f} M/s ({march_s / exact_s:.0f} times slower); the march disagrees "
      f"on {int((march != exact).sum())} lines ({100 * (march != exact).mean():.2f} %: "
      f"{int((march & ~exact).sum())} blocked that are clear, {int((~march & exact).sum())} clear that are "
      f"blocked)")
