"""terracast: exact ray casting of elevation grids.

Height fields come from files (``HeightField.open``) or NumPy arrays (``HeightField.from_array``); batches of
rays are traced against the exact bilinear surface (or triangles, or Embree) with ``intersect`` and
``occluded``. Coordinates are local metres: x east, y north, z up, origin at the south-west sample.
"""

from ._core import HeightField, __version__

__all__ = ["HeightField", "__version__"]
