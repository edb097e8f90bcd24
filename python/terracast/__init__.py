"""terracast: exact ray casting of elevation grids.

Height fields come from files (``HeightField.open``) or NumPy arrays (``HeightField.from_array``). Batches of
rays are traced against the exact bilinear surface (or triangles, or Embree) with ``intersect`` and
``occluded``; the map products (``shadow``, ``horizon``, ``viewshed``, ``svf``, ``insolation``, ``map_view``)
and perspective renders (``render``) come back as NumPy arrays holding what the command-line tool writes.
``accuracy`` and ``compare`` return the JSON reports as dictionaries; ``render_scene`` renders a scene file.
Coordinates are local metres: x east, y north, z up, origin at the south-west vertex; map arrays have the
DEM's shape with row 0 at the north, as rasters are stored.
"""

from ._core import HeightField, __version__, accuracy, compare, render_scene

__all__ = ["HeightField", "__version__", "accuracy", "compare", "render_scene"]
