from typing import Dict, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

class HeightField:
    @staticmethod
    def open(path: str, cell_size: float = 1.0, height_scale: float = 1.0) -> "HeightField": ...
    @staticmethod
    def from_array(
        heights: npt.ArrayLike,
        cell_size: Optional[Union[float, Tuple[float, float]]] = None,
        nodata: Optional[float] = None,
        transform: Optional[Sequence[float]] = None,
        crs: str = "",
    ) -> "HeightField": ...
    @property
    def width(self) -> int: ...
    @property
    def height(self) -> int: ...
    @property
    def cell_size(self) -> Tuple[float, float]: ...
    @property
    def min_height(self) -> float: ...
    @property
    def max_height(self) -> float: ...
    @property
    def nodata_count(self) -> int: ...
    def intersect(
        self, origins: npt.ArrayLike, directions: npt.ArrayLike, method: str = "bilinear"
    ) -> Dict[str, np.ndarray]: ...
    def occluded(
        self, origins: npt.ArrayLike, directions: npt.ArrayLike, method: str = "bilinear"
    ) -> np.ndarray: ...
