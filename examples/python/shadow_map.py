"""Cast shadows at a date and time beside GDAL's hillshade, for a DEM read with GDAL's Python bindings.

    python3 examples/python/shadow_map.py [DEM] [ISO-TIME] [OUT.png]

The DEM goes to terracast as a NumPy array with its geotransform and CRS; terracast places the sun where it
stands at that instant over the DEM's centre and traces, from every vertex, whether terrain hides it. GDAL's
hillshade (gdaldem) shades each cell by its own slope only, so it shows no cast shadow: the right panel shows
what the left one misses.
"""

import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from osgeo import gdal  # noqa: E402

import terracast  # noqa: E402

gdal.UseExceptions()
dem = sys.argv[1] if len(sys.argv) > 1 else "data-samples/usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif"
when = sys.argv[2] if len(sys.argv) > 2 else "2026-11-25T23:00Z"
out = sys.argv[3] if len(sys.argv) > 3 else "shadow-map.png"

ds = gdal.Open(dem)
band = ds.GetRasterBand(1)
heights = band.ReadAsArray()
hf = terracast.HeightField.from_array(heights, nodata=band.GetNoDataValue(), transform=ds.GetGeoTransform(),
                                      crs=ds.GetProjection())
azimuth, elevation = hf.sun_at(when)
shadow = hf.shadow(sun_time=when)  # uint8: 1 shadowed, 0 lit, 255 where the DEM has no height
hillshade = gdal.DEMProcessing("/vsimem/hillshade.tif", ds, "hillshade", azimuth=azimuth,
                               altitude=elevation).ReadAsArray()

x0, dx, _, y0, _, dy = ds.GetGeoTransform()
extent = [x0, x0 + dx * ds.RasterXSize, y0 + dy * ds.RasterYSize, y0]
land = shadow != 255
shaded = np.ma.masked_where(~land, hillshade)
cast = np.ma.masked_where(shadow != 1, np.ones_like(hillshade))

fig, axes = plt.subplots(1, 2, figsize=(10, 7.4), sharey=True)
axes[0].imshow(shaded, cmap="gray", extent=extent)
axes[0].set_title("GDAL hillshade (each cell's own slope)")
axes[1].imshow(shaded, cmap="gray", extent=extent)
axes[1].imshow(cast, cmap="Blues", vmin=0, vmax=1.4, alpha=0.6, extent=extent)
axes[1].set_title(f"terracast cast shadows: {100 * (shadow[land] == 1).mean():.1f} % of the land")
for ax in axes:
    ax.set_xlabel("easting (m)")
    ax.ticklabel_format(style="plain", useOffset=False)
axes[0].set_ylabel("northing (m)")
fig.suptitle(f"{when}: sun at azimuth {azimuth:.1f}, elevation {elevation:.1f} degrees")
fig.tight_layout()
fig.savefig(out, dpi=90)
print(f"{out}: sun at {azimuth:.2f}, {elevation:.2f} degrees; {int((shadow == 1).sum())} of {int(land.sum())} "
      f"vertices in cast shadow")
