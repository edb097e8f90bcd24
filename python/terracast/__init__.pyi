import datetime
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

Progress = Optional[Callable[[float, int], Any]]
Sun = Union[str, Tuple[float, float], Sequence[float]]
Instant = Union[str, datetime.datetime]

class HeightField:
    @staticmethod
    def open(path: str, cell_size: float = 1.0, height_scale: float = 1.0) -> "HeightField": ...
    @staticmethod
    def from_array(
        heights: npt.ArrayLike,
        cell_size: Optional[Union[float, Tuple[float, float]]] = None,
        nodata: Optional[float] = None,
        transform: Optional[Any] = None,
        crs: Optional[Union[str, int, Any]] = None,
    ) -> "HeightField": ...
    @property
    def width(self) -> int: ...
    @property
    def height(self) -> int: ...
    @property
    def shape(self) -> Tuple[int, int]: ...
    @property
    def cell_size(self) -> Tuple[float, float]: ...
    @property
    def min_height(self) -> float: ...
    @property
    def max_height(self) -> float: ...
    @property
    def nodata_count(self) -> int: ...
    @property
    def crs(self) -> str: ...
    @property
    def transform(self) -> Optional[Tuple[float, float, float, float, float, float]]: ...
    def intersect(
        self,
        origins: npt.ArrayLike,
        directions: npt.ArrayLike,
        method: str = "bilinear",
        t_max: Optional[Union[float, npt.ArrayLike]] = None,
        threads: int = 0,
        progress: Progress = None,
    ) -> Dict[str, np.ndarray]: ...
    def occluded(
        self,
        origins: npt.ArrayLike,
        directions: npt.ArrayLike,
        method: str = "bilinear",
        t_max: Optional[Union[float, npt.ArrayLike]] = None,
        threads: int = 0,
        progress: Progress = None,
    ) -> np.ndarray: ...
    def sun_at(self, when: Instant) -> Tuple[float, float]: ...
    def shadow(
        self,
        sun: Sun = (315.0, 35.0),
        *,
        sun_size: float = 0.0,
        sun_time: Optional[Union[Instant, Sequence[Instant]]] = None,
        max_distance: float = 0.0,
        curvature_coeff: float = 0.0,
        method: str = "bilinear",
        threads: int = 0,
        progress: Progress = None,
    ) -> np.ndarray: ...
    def horizon(
        self,
        azimuth: Optional[float] = None,
        *,
        azimuths: Optional[Union[str, Sequence[float]]] = None,
        max_distance: float = 0.0,
        curvature_coeff: float = 0.0,
        method: str = "bilinear",
        threads: int = 0,
        progress: Progress = None,
    ) -> np.ndarray: ...
    def viewshed(
        self,
        observer: Optional[Tuple[float, float]] = None,
        *,
        observers: Optional[str] = None,
        lonlat: bool = False,
        observer_height: float = 1.7,
        target_height: float = 0.0,
        values: str = "visible",
        curvature_coeff: float = 0.85714,
        max_distance: float = 0.0,
        method: str = "bilinear",
        threads: int = 0,
        progress: Progress = None,
    ) -> np.ndarray: ...
    def svf(
        self,
        *,
        directions: int = 16,
        max_distance: float = 0.0,
        curvature_coeff: float = 0.0,
        method: str = "bilinear",
        threads: int = 0,
        progress: Progress = None,
    ) -> np.ndarray: ...
    def insolation(
        self,
        date: str,
        *,
        step: str = "30m",
        day_step: int = 1,
        linke: float = 3.0,
        albedo: float = 0.2,
        max_distance: float = 0.0,
        curvature_coeff: float = 0.0,
        method: str = "bilinear",
        threads: int = 0,
        progress: Progress = None,
    ) -> np.ndarray: ...
    def map_view(
        self,
        sun: Sun = (315.0, 35.0),
        *,
        sun_time: Optional[Instant] = None,
        scale: float = 1.0,
        no_shadows: bool = False,
        sky_samples: int = -1,
        colour: str = "grey",
        hillshade_blend: float = 0.0,
        exaggeration: float = 1.0,
        method: str = "bilinear",
        threads: int = 0,
        progress: Progress = None,
    ) -> np.ndarray: ...
    def render(
        self,
        *,
        size: Union[str, Tuple[int, int]] = (1280, 720),
        sun: Sun = (315.0, 35.0),
        sun_time: Optional[Instant] = None,
        exaggeration: float = 1.0,
        camera: Optional[str] = None,
        view: str = "perspective",
        method: str = "bilinear",
        threads: int = 0,
        spp: int = 1,
        sampler: str = "stratified",
        filter: str = "box",
        adaptive: Optional[float] = None,
        sky: str = "physical",
        haze: float = 1.0,
        sky_samples: int = -1,
        seed: int = 0,
        normals: str = "smooth",
        colour: Optional[str] = None,
        drape: Optional[str] = None,
        no_base: bool = False,
        background: str = "neutral",
        linear: bool = False,
        progress: Progress = None,
    ) -> np.ndarray: ...

def accuracy(dem: Union[HeightField, str], *, rays: int = 100000, seed: int = 1, progress: Progress = None) -> Dict[str, Any]: ...
def compare(
    dem: Union[HeightField, str],
    *,
    size: Sequence[int] = (640, 480),
    sun: Sequence[float] = (315.0, 35.0),
    exaggeration: float = 1.0,
    camera: Optional[str] = None,
    methods: Sequence[str] = (),
    threads: int = 0,
    progress: Progress = None,
) -> Dict[str, Any]: ...
def render_scene(
    path: str,
    *,
    size: Optional[Tuple[int, int]] = None,
    spp: int = 0,
    threads: int = -1,
    seed: int = -1,
    method: Optional[str] = None,
    allow_paths: bool = False,
    linear: bool = False,
    progress: Progress = None,
) -> np.ndarray: ...
