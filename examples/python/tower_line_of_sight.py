"""Which of a million points on the ground see the top of a tower? One batch of exact sight lines.

    python3 examples/python/tower_line_of_sight.py [DEM] [POINTS]

Every point stands 1.7 m above the terrain (an observer's eyes); the tower's top is 60 m above the ground at a
place on the DEM. The sight line from the top to a point is the ray top + t (point - top) for t in [0, 1]:
`occluded(..., t_max=1.0)` says whether terrain cuts it, traced against the exact bilinear surface on all
cores with the GIL released.
"""

import sys
import time

import numpy as np

import terracast

dem = sys.argv[1] if len(sys.argv) > 1 else "data-samples/usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif"
n = int(sys.argv[2]) if len(sys.argv) > 2 else 1_000_000
hf = terracast.HeightField.open(dem)
width_m = (hf.width - 1) * hf.cell_size[0]
height_m = (hf.height - 1) * hf.cell_size[1]


def ground(xy):
    """The terrain's height under local points (x, y), and whether there is terrain there (not nodata)."""
    above = np.column_stack([xy, np.full(len(xy), hf.max_height + 100.0)])
    down = hf.intersect(above, np.tile([0.0, 0.0, -1.0], (len(xy), 1)))
    return down["point"][:, 2], down["hit"]


tower = np.array([[0.40 * width_m, 0.30 * height_m]])
tower_ground, on_land = ground(tower)
assert on_land[0], "the tower stands over nodata: pick another place"
top = np.array([tower[0, 0], tower[0, 1], tower_ground[0] + 60.0])

rng = np.random.default_rng(1)
xy = np.column_stack([rng.uniform(0, width_m, n), rng.uniform(0, height_m, n)])
z, on_land = ground(xy)
points = np.column_stack([xy, z + 1.7])[on_land]

start = time.perf_counter()
blocked = hf.occluded(np.broadcast_to(top, points.shape), points - top, t_max=1.0)
seconds = time.perf_counter() - start
sees = ~blocked
print(f"{int(sees.sum())} of {len(points)} points on the ground ({100 * sees.mean():.1f} %) see the tower's top "
      f"at {top[0]:.0f}, {top[1]:.0f}, {top[2]:.0f} m; {len(points) / seconds / 1e6:.2f} M sight lines/s "
      f"({seconds:.2f} s)")
