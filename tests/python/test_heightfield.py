"""terracast's Python module: height fields from arrays and files, and batch ray queries, checked against
planes whose hits are known exactly, against GDAL's own reading of a sample DEM, and against Embree."""

import os

import numpy as np
import pytest

import terracast

SAMPLES = os.path.join(os.path.dirname(__file__), "..", "..", "data-samples")
ST_HELENS = os.path.join(SAMPLES, "usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif")


def tilted_plane(dtype=np.float32, rows=21, cols=31, cell=10.0):
    """Heights 2 + 0.5 x + 0.25 y (metres, x east and y north from the south-west sample), stored as a raster:
    row 0 at the north edge."""
    x = np.arange(cols) * cell
    y = (rows - 1 - np.arange(rows)) * cell
    return (2.0 + 0.5 * x[np.newaxis, :] + 0.25 * y[:, np.newaxis]).astype(dtype)


def vertical_rays(n, width_m, height_m, seed=1):
    rng = np.random.default_rng(seed)
    origins = np.column_stack([rng.uniform(0, width_m, n), rng.uniform(0, height_m, n), np.full(n, 1000.0)])
    directions = np.tile([0.0, 0.0, -1.0], (n, 1))
    return origins, directions


def test_version_and_summary():
    assert terracast.__version__.count(".") == 2
    hf = terracast.HeightField.from_array(tilted_plane(), cell_size=10.0)
    text = repr(hf)
    assert "31 x 21 vertices" in text and "cells 10 x 10 m" in text


@pytest.mark.parametrize("method,tolerance", [("bilinear-double", 1e-9), ("bilinear", 5e-5), ("triangles", 5e-5)])
def test_a_plane_is_hit_exactly_where_it_stands(method, tolerance):
    # The float kernels ("bilinear", "triangles") work to float precision at 1000 m: about 6e-5 m.
    hf = terracast.HeightField.from_array(tilted_plane(), cell_size=10.0)
    origins, directions = vertical_rays(10000, 300.0, 200.0)
    r = hf.intersect(origins, directions, method=method)
    expected = 2.0 + 0.5 * origins[:, 0] + 0.25 * origins[:, 1]
    assert r["hit"].all()
    np.testing.assert_allclose(r["point"][:, 2], expected, rtol=0, atol=tolerance)
    np.testing.assert_allclose(r["t"], 1000.0 - expected, rtol=0, atol=tolerance)
    # The plane's unit normal (-0.5, -0.25, 1) / |.|, pointing up.
    n = np.array([-0.5, -0.25, 1.0]) / np.linalg.norm([-0.5, -0.25, 1.0])
    np.testing.assert_allclose(r["normal"], np.tile(n, (10000, 1)), atol=1e-6)
    # Beside the grid every ray misses: t is inf and the point NaN.
    far = hf.intersect(origins + [1000.0, 0.0, 0.0], directions)
    assert not far["hit"].any() and np.isinf(far["t"]).all() and np.isnan(far["point"]).all()


def test_row_zero_is_north():
    heights = np.zeros((5, 5), dtype=np.float32)
    heights[0, 2] = 100.0  # the north edge's middle sample
    hf = terracast.HeightField.from_array(heights, cell_size=1.0)
    r = hf.intersect(np.array([[2.0, 4.0, 500.0], [2.0, 0.0, 500.0]]), np.array([[0, 0, -1.0], [0, 0, -1.0]]),
                     method="bilinear-double")
    np.testing.assert_allclose(r["point"][:, 2], [100.0, 0.0], atol=1e-9)


@pytest.mark.parametrize("dtype", [np.int16, np.uint16, np.float32, np.float64])
def test_every_dtype_and_memory_order_gives_the_same_hits(dtype):
    plane = np.rint(tilted_plane(np.float64)).astype(dtype)
    reference = terracast.HeightField.from_array(plane.astype(np.float64), cell_size=(10.0, 10.0))
    origins, directions = vertical_rays(2000, 300.0, 200.0, seed=2)
    want = reference.intersect(origins, directions)["t"]
    for array in (plane, np.asfortranarray(plane)):
        got = terracast.HeightField.from_array(array, cell_size=10.0).intersect(origins, directions)["t"]
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-6)


def test_nodata_leaves_holes_and_nan_needs_nodata():
    heights = tilted_plane()
    heights[10, 15] = -9999.0
    hf = terracast.HeightField.from_array(heights, cell_size=10.0, nodata=-9999.0)
    assert hf.nodata_count == 1
    # The hole's vertex (x 150, y 100) touches four cells; a ray into any of them misses.
    r = hf.intersect(np.array([[145.0, 95.0, 1000.0], [100.0, 50.0, 1000.0]]), np.array([[0, 0, -1.0]] * 2))
    assert list(r["hit"]) == [False, True]
    heights[10, 15] = np.nan
    with pytest.raises(ValueError, match="finite"):
        terracast.HeightField.from_array(heights, cell_size=10.0)
    assert terracast.HeightField.from_array(heights, cell_size=10.0, nodata=np.nan).nodata_count == 1


def test_bad_arrays_and_options_are_refused():
    with pytest.raises(ValueError, match="2-D"):
        terracast.HeightField.from_array(np.zeros((3, 3, 3), dtype=np.float32))
    with pytest.raises(TypeError, match="complex"):
        terracast.HeightField.from_array(np.zeros((3, 3), dtype=np.complex64))
    with pytest.raises(ValueError, match="cell_size"):
        terracast.HeightField.from_array(np.zeros((3, 3), dtype=np.float32), cell_size=-1.0)
    with pytest.raises(ValueError, match="2 x 2"):
        terracast.HeightField.from_array(np.zeros((1, 5), dtype=np.float32))
    hf = terracast.HeightField.from_array(np.zeros((3, 3), dtype=np.float32), transform=(500000, 30, 0, 4000000, 0, -20))
    assert hf.cell_size == (30.0, 20.0)
    with pytest.raises(ValueError, match="method"):
        hf.intersect(np.zeros((1, 3)), np.array([[0, 0, -1.0]]), method="bilinar")
    with pytest.raises(ValueError, match="origins"):
        hf.intersect(np.zeros((4, 2)), np.zeros((4, 3)))


def test_a_dem_file_matches_gdals_reading_of_it():
    gdal = pytest.importorskip("osgeo.gdal")
    ds = gdal.Open(ST_HELENS)
    band = ds.GetRasterBand(1)
    values = band.ReadAsArray()
    hf = terracast.HeightField.open(ST_HELENS)
    assert (hf.width, hf.height) == (ds.RasterXSize, ds.RasterYSize)
    assert hf.nodata_count == int((values == band.GetNoDataValue()).sum())
    valid = values[values != band.GetNoDataValue()]
    assert hf.min_height == pytest.approx(valid.min()) and hf.max_height == pytest.approx(valid.max())
    with pytest.raises(FileNotFoundError, match="no such file"):
        terracast.HeightField.open(os.path.join(SAMPLES, "missing.tif"))
    with pytest.raises(ValueError, match="README.md"):
        terracast.HeightField.open(os.path.join(SAMPLES, "README.md"))


def test_exact_and_embree_agree_on_a_real_dem_and_occlusion_matches_hits():
    hf = terracast.HeightField.open(ST_HELENS)
    w, h = (hf.width - 1) * hf.cell_size[0], (hf.height - 1) * hf.cell_size[1]
    rng = np.random.default_rng(3)
    n = 100000
    origins = np.column_stack([rng.uniform(0, w, n), rng.uniform(0, h, n), rng.uniform(2600, 4000, n)])
    directions = np.column_stack([rng.normal(size=n), rng.normal(size=n), -np.abs(rng.normal(size=n)) - 0.2])
    exact = hf.intersect(origins, directions)
    triangles = hf.intersect(origins, directions, method="embree")
    agree = (exact["hit"] == triangles["hit"]).mean()
    assert agree > 0.999
    both = exact["hit"] & triangles["hit"]
    assert np.median(np.abs(exact["t"][both] - triangles["t"][both])) < 1.0
    # Occlusion is the any-hit query: it agrees with the first-hit query but for rays that graze the surface
    # within float tolerance.
    assert (hf.occluded(origins, directions) != exact["hit"]).mean() < 1e-4


def test_t_max_ends_each_search_where_asked():
    hf = terracast.HeightField.from_array(tilted_plane(), cell_size=10.0)
    origins, directions = vertical_rays(1000, 300.0, 200.0, seed=5)
    ground = 2.0 + 0.5 * origins[:, 0] + 0.25 * origins[:, 1]
    reach = 1000.0 - ground  # where each ray meets the plane
    # Half the rays stop 1 cm short of the plane, half 1 cm beyond it.
    short = np.arange(1000) % 2 == 0
    t_max = np.where(short, reach - 0.01, reach + 0.01)
    r = hf.intersect(origins, directions, method="bilinear-double", t_max=t_max)
    assert np.array_equal(r["hit"], ~short)
    assert np.array_equal(hf.occluded(origins, directions, t_max=t_max), ~short)
    # One number for all: a sight line from above to a point on the far side of a ridge.
    assert not hf.occluded(origins, directions, t_max=float(reach.min()) - 0.01).any()
    with pytest.raises(ValueError, match="t_max"):
        hf.occluded(origins, directions, t_max=np.ones(3))
    with pytest.raises(ValueError, match="t_max"):
        hf.occluded(origins, directions, t_max=-1.0)


def test_exact_hits_match_the_long_double_reference_on_camera_grazing_and_vertex_rays():
    # 10^5 seeded rays on a real DEM, a third of each kind: steep camera-like rays, rays grazing the terrain
    # (a few metres above a surface point, nearly level), and rays aimed exactly at vertices. The exact method
    # in double precision and the independent long-double reference decide the same hits, at the same distances.
    gdal = pytest.importorskip("osgeo.gdal")
    hf = terracast.HeightField.open(ST_HELENS)
    dataset = gdal.Open(ST_HELENS)  # kept: a band outliving its dataset is invalid
    band = dataset.GetRasterBand(1)
    cx, cy = hf.cell_size
    w, h = (hf.width - 1) * cx, (hf.height - 1) * cy
    rng = np.random.default_rng(11)
    k = 33334
    camera_o = np.column_stack([rng.uniform(0, w, k), rng.uniform(0, h, k), rng.uniform(2600, 4000, k)])
    camera_d = np.column_stack([rng.normal(size=k), rng.normal(size=k), -np.abs(rng.normal(size=k)) - 0.2])
    start = np.column_stack([rng.uniform(0, w, k), rng.uniform(0, h, k)])
    ground = hf.intersect(np.column_stack([start, np.full(k, 5000.0)]), np.tile([0, 0, -1.0], (k, 1)))
    keep = ground["hit"]
    azimuth = rng.uniform(0, 2 * np.pi, k)
    graze_o = ground["point"][keep] + [0.0, 0.0, 2.0]
    graze_d = np.column_stack([np.sin(azimuth), np.cos(azimuth), rng.uniform(-0.02, 0.01, k)])[keep]
    # Vertices: (i cx, j cy, height), row j counted from the south; the raster's row 0 is north.
    heights = band.ReadAsArray().astype(np.float64)
    valid = heights != band.GetNoDataValue()
    # Vertices whose four cells all have heights (a valid vertex among holes has no surface through it).
    around = np.ones_like(valid[1:-1, 1:-1])
    for dr in (-1, 0, 1):
        for dc in (-1, 0, 1):
            around &= valid[1 + dr:valid.shape[0] - 1 + dr, 1 + dc:valid.shape[1] - 1 + dc]
    rows, cols = np.nonzero(around)
    pick = rng.choice(len(rows), k, replace=False)
    r, c = rows[pick] + 1, cols[pick] + 1
    vertex = np.column_stack([c * cx, (hf.height - 1 - r) * cy, heights[r, c]])
    vertex_o = vertex + np.column_stack([rng.uniform(-300, 300, k), rng.uniform(-300, 300, k),
                                         rng.uniform(200, 900, k)])
    origins = np.vstack([camera_o, graze_o, vertex_o])
    directions = np.vstack([camera_d, graze_d, vertex - vertex_o])
    exact = hf.intersect(origins, directions, method="bilinear-double")
    reference = hf.intersect(origins, directions, method="reference")
    assert len(origins) > 95000
    assert (exact["hit"] != reference["hit"]).mean() < 1e-4
    both = exact["hit"] & reference["hit"]
    assert np.abs(exact["t"][both] - reference["t"][both]).max() < 1e-6 * np.abs(reference["t"][both]).max()
    # A ray aimed at a vertex meets the terrain there or before, unless it only touches the surface at the vertex
    # (a peak it passes over): just beyond the vertex such a ray is above the surface again.
    aimed = slice(len(camera_o) + len(graze_o), None)
    assert exact["hit"][aimed].all()
    beyond = np.nonzero(exact["t"][aimed] > 1.0 + 1e-9)[0]
    assert len(beyond) <= 10
    after = vertex_o[beyond] + 1.001 * (vertex[beyond] - vertex_o[beyond])
    below = hf.intersect(after + [0.0, 0.0, 1e-9], np.tile([0, 0, -1.0], (len(beyond), 1)), method="bilinear-double")
    assert (below["point"][:, 2] < after[:, 2]).all()
