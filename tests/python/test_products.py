"""terracast's products as NumPy arrays: each equal, sample for sample, to what the command-line tool writes for
the same DEM and options (read back through GDAL's Python bindings); arrays placed by a geotransform and a CRS in
every accepted spelling against the same DEM read from its file; progress, Ctrl-C, the GIL and peak memory."""

import json
import os
import resource
import subprocess
import sys
import tempfile
import textwrap
import threading
import time

import numpy as np
import pytest
from osgeo import gdal

import terracast

gdal.UseExceptions()

SAMPLES = os.path.join(os.path.dirname(__file__), "..", "..", "data-samples")
ST_HELENS = os.path.join(SAMPLES, "usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif")
NICE = os.path.join(SAMPLES, "srtm3-n43e007-nice-maritime-alps-coast-geographic-int16.tif")
CLI = os.environ.get("TERRACAST_CLI", os.path.join(os.path.dirname(__file__), "..", "..", "build", "terracast"))


@pytest.fixture(scope="module")
def helens():
    return terracast.HeightField.open(ST_HELENS)


def run_cli(*args):
    done = subprocess.run([CLI, *args], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr


def cli_raster(tmp_path, command, *options):
    """The raster `terracast COMMAND ST_HELENS -o FILE OPTIONS` writes, as GDAL reads it: (rows, columns[, bands])
    in the file's type, float nodata as NaN."""
    out = str(tmp_path / f"{command}.tif")
    run_cli(command, ST_HELENS, "-o", out, "--quiet", *options) if command == "render" else run_cli(
        command, ST_HELENS, "-o", out, *options)
    ds = gdal.Open(out)
    bands = [ds.GetRasterBand(k + 1) for k in range(ds.RasterCount)]
    data = np.stack([b.ReadAsArray() for b in bands], axis=-1)
    nodata = bands[0].GetNoDataValue()
    if data.dtype == np.float32 and nodata is not None:
        data[data == np.float32(nodata)] = np.nan
    return data[:, :, 0] if data.shape[2] == 1 else data


def same_samples(a, b):
    assert a.dtype == b.dtype and a.shape == b.shape, (a.dtype, a.shape, b.dtype, b.shape)
    if a.dtype == np.float32:
        assert np.array_equal(np.isnan(a), np.isnan(b))
        assert np.array_equal(a.view(np.uint32)[~np.isnan(a)], b.view(np.uint32)[~np.isnan(b)])
    else:
        assert np.array_equal(a, b)


def summit_observer(hf):
    x0, dx, _, y0, _, dy = hf.transform
    return (x0 + dx * 180.5, y0 + dy * 210.5)


def test_every_map_product_equals_the_cli_file_sample_for_sample(helens, tmp_path):
    same_samples(helens.shadow((315, 20)), cli_raster(tmp_path, "shadow", "--sun", "315,20"))
    same_samples(helens.shadow((200, 12), sun_size=0.53, max_distance=3000),
                 cli_raster(tmp_path, "shadow", "--sun", "200,12", "--sun-size", "0.53", "--max-distance", "3000"))
    same_samples(helens.shadow(sun_time="2026-06-21T14:00Z/2026-06-21T20:00Z/3h"),
                 cli_raster(tmp_path, "shadow", "--sun-time", "2026-06-21T14:00Z/2026-06-21T20:00Z/3h"))
    same_samples(helens.horizon(azimuths="0:360:45"), cli_raster(tmp_path, "horizon", "--azimuths", "0:360:45"))
    same_samples(helens.horizon(225.0, curvature_coeff=0.85714),
                 cli_raster(tmp_path, "horizon", "--azimuth", "225", "--curvature-coeff", "0.85714"))
    x, y = summit_observer(helens)
    same_samples(helens.viewshed((x, y)), cli_raster(tmp_path, "viewshed", "--observer", f"{x},{y}"))
    same_samples(helens.viewshed((x, y), values="height", observer_height=10),
                 cli_raster(tmp_path, "viewshed", "--observer", f"{x},{y}", "--values", "height",
                            "--observer-height", "10"))
    same_samples(helens.svf(directions=8), cli_raster(tmp_path, "svf", "--directions", "8"))
    same_samples(helens.insolation("2026-03-20", step="2h"),
                 cli_raster(tmp_path, "insolation", "--date", "2026-03-20", "--step", "2h"))
    same_samples(helens.map_view((120, 30), colour="ramp", sky_samples=4),
                 cli_raster(tmp_path, "render", "--view", "map", "--sun", "120,30", "--colour", "ramp",
                            "--sky-samples", "4"))


@pytest.mark.parametrize("dem", ["N44W072.srtm3-white-mountains-nh.hgt",
                                 "srtm3-n43e007-nice-maritime-alps-coast-geographic-int16.tif",
                                 "landfire-storm-lake-mt-utm12n-int16-small-nodata.tif"])
def test_geographic_and_other_dems_give_the_cli_samples_too(dem, tmp_path):
    path = os.path.join(SAMPLES, dem)
    hf = terracast.HeightField.open(path)
    for command, options, ours in [
            ("shadow", ["--sun-time", "2026-12-21T14:00Z"], lambda: hf.shadow(sun_time="2026-12-21T14:00Z")),
            ("shadow", ["--sun-time", "2026-12-21T13:00Z/2026-12-21T15:00Z/1h"],
             lambda: hf.shadow(sun_time=["2026-12-21T13:00Z", "2026-12-21T14:00Z", "2026-12-21T15:00Z"])),
            ("horizon", ["--azimuth", "100", "--max-distance", "5000"],
             lambda: hf.horizon(100.0, max_distance=5000.0, threads=1))]:
        out = str(tmp_path / f"{command}.tif")
        run_cli(command, path, "-o", out, *options)
        ds = gdal.Open(out)
        bands = [ds.GetRasterBand(k + 1) for k in range(ds.RasterCount)]
        theirs = np.stack([b.ReadAsArray() for b in bands], axis=-1)
        if theirs.dtype == np.float32:
            theirs[theirs == np.float32(bands[0].GetNoDataValue())] = np.nan
        same_samples(ours(), theirs[:, :, 0] if len(bands) == 1 else theirs)


def test_products_take_the_sun_as_text_tuple_time_or_datetime(helens):
    import datetime
    assert np.array_equal(helens.shadow("315,20"), helens.shadow((315, 20)))
    when = datetime.datetime(2026, 6, 21, 8, 0, tzinfo=datetime.timezone(datetime.timedelta(hours=-7)))
    one = helens.shadow(sun_time=when)
    assert one.shape == helens.shape
    assert np.array_equal(one, helens.shadow(sun_time="2026-06-21T15:00Z"))
    assert np.array_equal(one, helens.shadow(sun_time=["2026-06-21T15:00Z"])[:, :, 0])
    # sun_at says where sun_time puts the sun: in the afternoon, west of south and above the horizon.
    azimuth, elevation = helens.sun_at("2026-06-21T23:00Z")
    assert 200 < azimuth < 300 and 10 < elevation < 50
    assert np.array_equal(helens.shadow((azimuth, elevation)), helens.shadow(sun_time="2026-06-21T23:00Z"))


def test_a_render_equals_the_cli_picture(helens, tmp_path):
    out = str(tmp_path / "view.png")
    run_cli("render", ST_HELENS, "-o", out, "--quiet", "--size", "160x90", "--sun", "290,25", "--spp", "2")
    png = gdal.Open(out).ReadAsArray().transpose(1, 2, 0)
    picture = helens.render(size=(160, 90), sun=(290, 25), spp=2)
    assert picture.dtype == np.uint8 and picture.shape == (90, 160, 3)
    assert np.array_equal(picture, png)
    # Exaggerated (the file opened again as --exaggeration opens it), from another view.
    out = str(tmp_path / "fisheye.png")
    run_cli("render", ST_HELENS, "-o", out, "--quiet", "--size", "64x64", "--exaggeration", "2.5", "--view",
            "orthographic", "--colour", "#a08060", "--no-base", "--sky", "gradient")
    png = gdal.Open(out).ReadAsArray().transpose(1, 2, 0)
    assert np.array_equal(helens.render(size="64x64", exaggeration=2.5, view="orthographic", colour="#a08060",
                                        no_base=True, sky="gradient"), png)
    # The map view at another scale than the DEM's own: one picture, as the command writes it.
    out = str(tmp_path / "map.tif")
    run_cli("render", ST_HELENS, "-o", out, "--quiet", "--view", "map", "--scale", "0.5", "--no-shadows")
    tif = gdal.Open(out).ReadAsArray().transpose(1, 2, 0)
    assert np.array_equal(helens.map_view(scale=0.5, no_shadows=True), tif)
    linear = helens.render(size=(160, 90), sun=(290, 25), spp=2, linear=True)
    assert linear.dtype == np.float32
    # The bytes are the linear values in sRGB's encoding (IEC 61966-2-1), written out here.
    c = np.clip(linear.astype(np.float64), 0.0, 1.0)
    encoded = np.where(c <= 0.0031308, 12.92 * c, 1.055 * c ** (1 / 2.4) - 0.055)
    assert np.abs(np.rint(encoded * 255) - picture).max() <= 1


def test_a_scene_renders_as_the_cli_renders_it(tmp_path):
    scene = os.path.join(SAMPLES, "lake.toml")
    out = str(tmp_path / "scene.png")
    run_cli("scene", scene, "-o", out, "--size", "96x54", "--spp", "1", "--quiet")
    png = gdal.Open(out).ReadAsArray().transpose(1, 2, 0)
    assert np.array_equal(terracast.render_scene(scene, size=(96, 54), spp=1), png)


def test_reports_are_the_cli_json_as_dicts(helens, tmp_path):
    out = str(tmp_path / "accuracy.json")
    run_cli("accuracy", ST_HELENS, "--rays", "3000", "--seed", "7", "--json", out)
    with open(out) as f:
        cli = json.load(f)
    ours = terracast.accuracy(helens, rays=3000, seed=7)
    assert ours.keys() == cli.keys()
    assert [m["name"] for m in ours["methods"]] == [m["name"] for m in cli["methods"]]
    # Everything but the timings is decided by the seed.
    for a, b in zip(ours["methods"], cli["methods"]):
        for timing in ("rays_per_s", "primary_rays_per_s"):
            a.pop(timing), b.pop(timing)
        assert a == b
    out = str(tmp_path / "compare.json")
    run_cli("compare", ST_HELENS, "--size", "64x48", "--methods", "bilinear,triangles", "--json", out)
    with open(out) as f:
        cli = json.load(f)
    ours = terracast.compare(ST_HELENS, size=(64, 48), methods=["bilinear", "triangles"])
    assert ours.keys() == cli.keys()
    for a, b in zip(ours["methods"], cli["methods"]):
        assert a.keys() == b.keys() and a["name"] == b["name"]
        assert a["hit_agreement"] == b["hit_agreement"] and a["t_error_m"] == b["t_error_m"]


def gdal_array_and_georeference(path):
    ds = gdal.Open(path)
    band = ds.GetRasterBand(1)
    return band.ReadAsArray(), band.GetNoDataValue(), ds.GetGeoTransform(), ds.GetProjection()


@pytest.mark.parametrize("spelling", ["gdal+wkt", "affine+epsg", "affine9+proj", "to_gdal+to_wkt"])
def test_an_array_placed_by_transform_and_crs_is_the_file(helens, spelling):
    heights, nodata, gt, wkt = gdal_array_and_georeference(ST_HELENS)

    class Affine(tuple):  # what rasterio's Affine offers
        def to_gdal(self):
            return gt

    class Crs:
        def to_wkt(self):
            return wkt

    transform, crs = {
        "gdal+wkt": (gt, wkt),
        "affine+epsg": ((gt[1], 0.0, gt[0], 0.0, gt[5], gt[3]), 26710),
        "affine9+proj": ((gt[1], 0.0, gt[0], 0.0, gt[5], gt[3], 0.0, 0.0, 1.0),
                         "+proj=utm +zone=10 +datum=NAD27 +units=m +no_defs"),
        "to_gdal+to_wkt": (Affine((1, 2, 3)), Crs()),
    }[spelling]
    hf = terracast.HeightField.from_array(heights, nodata=nodata, transform=transform, crs=crs)
    assert hf.cell_size == helens.cell_size and hf.shape == helens.shape and hf.transform == helens.transform
    same_samples(hf.shadow(sun_time="2026-06-21T16:00Z"), helens.shadow(sun_time="2026-06-21T16:00Z"))
    x, y = summit_observer(helens)
    same_samples(hf.viewshed((x, y)), helens.viewshed((x, y)))


def test_a_geographic_array_is_converted_to_metres_as_its_file_is():
    heights, nodata, gt, wkt = gdal_array_and_georeference(NICE)
    from_file = terracast.HeightField.open(NICE)
    hf = terracast.HeightField.from_array(heights, nodata=nodata, transform=gt, crs="EPSG:4326")
    assert hf.cell_size == pytest.approx(from_file.cell_size, rel=1e-12)
    same_samples(hf.horizon(90.0), from_file.horizon(90.0))
    # A south-up array (a positive row step) is the same terrain turned over.
    flipped = (gt[0], gt[1], 0.0, gt[3] + gt[5] * heights.shape[0], 0.0, -gt[5])
    up = terracast.HeightField.from_array(heights[::-1].copy(), nodata=nodata, transform=flipped, crs=wkt)
    same_samples(up.horizon(90.0), from_file.horizon(90.0))


def test_product_arguments_are_refused_with_their_names(helens):
    with pytest.raises(ValueError, match="sun: expected"):
        helens.shadow("315")
    with pytest.raises(ValueError, match="sun: expected finite"):
        helens.shadow((float("nan"), 30.0))
    with pytest.raises(ValueError, match="rendering 65536x65536 needs"):
        helens.render(size=(65536, 65536))
    with pytest.raises(ValueError, match="--spp"):
        helens.render(spp=0, exaggeration=3.0)
    with pytest.raises(ValueError, match="sun_time: expected a timezone-aware"):
        import datetime
        helens.shadow(sun_time=datetime.datetime(2026, 6, 21, 12))
    with pytest.raises(ValueError, match="azimuth"):
        helens.horizon()
    with pytest.raises(ValueError, match="--sun-size|sun-size"):
        helens.shadow(sun_size=40)
    with pytest.raises(ValueError, match="values: expected visible, angle or height"):
        helens.viewshed(summit_observer(helens), values="seen")
    with pytest.raises(ValueError, match="lies outside the DEM"):
        helens.viewshed((0.0, 0.0))
    with pytest.raises(ValueError, match="view: expected"):
        helens.render(view="map")
    with pytest.raises(ValueError, match="colour: expected"):
        helens.render(colour="#12345")
    with pytest.raises(ValueError, match="method: expected"):
        helens.horizon(10.0, method="bvh")
    with pytest.raises(ValueError, match="threads"):
        helens.horizon(10.0, threads=-2)
    with pytest.raises(ValueError, match="no CRS|CRS"):
        terracast.HeightField.from_array(np.zeros((4, 4), np.float32)).shadow(sun_time="2026-06-21T12:00Z")
    with pytest.raises(ValueError, match="crs: expected WKT"):
        terracast.HeightField.from_array(np.zeros((4, 4), np.float32), transform=(0, 1, 0, 4, 0, -1), crs="EPSG:0")
    with pytest.raises(ValueError, match="crs: give it with a transform"):
        terracast.HeightField.from_array(np.zeros((4, 4), np.float32), crs=4326)
    with pytest.raises(ValueError, match="rotated"):
        terracast.HeightField.from_array(np.zeros((4, 4), np.float32), transform=(0, 1, 0.5, 4, 0, -1))
    with pytest.raises(ValueError, match="scene|toml|no such"):
        terracast.render_scene(os.path.join(SAMPLES, "missing.toml"))


@pytest.fixture(scope="module")
def waves():
    """A million vertices of rolling terrain: 16 horizons a vertex over the whole grid take tens of seconds."""
    n = 1000
    y, x = np.mgrid[0:n, 0:n].astype(np.float32)
    return terracast.HeightField.from_array(200.0 * np.sin(x / 37.0) * np.cos(y / 53.0) + 0.05 * x, cell_size=10.0)


def test_progress_is_reported_and_a_raising_callback_stops_the_work(waves):
    seen = []
    waves.horizon(45.0, max_distance=300.0, progress=lambda f, rays: seen.append((f, rays)))
    assert seen[-1][0] == 1.0 and seen[-1][1] > 0
    assert all(a[0] <= b[0] for a, b in zip(seen, seen[1:]))

    def stop(f, rays):
        if f > 0.0:
            raise RuntimeError("enough")

    start = time.monotonic()
    with pytest.raises(RuntimeError, match="enough"):
        waves.horizon(azimuths="0:360:22.5", progress=stop)
    assert time.monotonic() - start < 5.0


def test_ctrl_c_stops_the_work_between_tiles_and_raises_keyboard_interrupt(waves):
    import _thread
    seen = []
    timer = threading.Timer(0.3, _thread.interrupt_main)
    timer.start()
    start = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        waves.horizon(azimuths="0:360:22.5", progress=lambda f, rays: seen.append(f))
    elapsed = time.monotonic() - start
    timer.join()
    # The whole map takes about 30 s on two cores: the work stopped where it was.
    assert elapsed < 3.0 and (not seen or seen[-1] < 0.5)
    # The next call runs normally.
    assert waves.horizon(0.0, max_distance=100.0).shape == waves.shape


def test_ctrl_c_stops_the_calls_of_other_threads_too(waves):
    import _thread
    other = {}

    def long_call():
        start = time.monotonic()
        try:
            waves.horizon(azimuths="0:360:22.5")
            other["end"] = "finished"
        except KeyboardInterrupt:
            other["end"] = "interrupted"
        other["seconds"] = time.monotonic() - start

    thread = threading.Thread(target=long_call)
    thread.start()
    time.sleep(0.2)
    timer = threading.Timer(0.3, _thread.interrupt_main)
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        waves.horizon(azimuths="0:360:22.5")
    thread.join(20.0)
    timer.join()
    assert other["end"] == "interrupted" and other["seconds"] < 3.0, other
    assert waves.horizon(0.0, max_distance=100.0).shape == waves.shape


def test_the_gil_is_released_while_a_product_is_computed(waves):
    ticks = [0]
    running = [True]

    def count():
        while running[0]:
            ticks[0] += 1

    t = threading.Thread(target=count)
    t.start()
    start = time.monotonic()
    waves.horizon(azimuths="0:360:45", max_distance=500.0)
    elapsed = time.monotonic() - start
    running[0] = False
    t.join()
    # A Python thread holding the GIL counts millions a second; one kept out of it would barely count.
    assert elapsed > 0.1 and ticks[0] > 100000 * elapsed, (ticks[0], elapsed)


def test_peak_memory_holds_the_result_once():
    # In a fresh process: the growth of the peak resident size (Linux's VmHWM, reset through clear_refs) while a
    # float32 horizon map of 16 M vertices (61 MiB) is computed. Holding the map twice (a whole raster, then the
    # array) would add another 61 MiB.
    code = textwrap.dedent("""
        import numpy as np, terracast
        def status(key):
            with open("/proc/self/status") as f:
                return next(int(line.split()[1]) / 1024.0 for line in f if line.startswith(key))
        n = 4000
        heights = (np.arange(n, dtype=np.float32)[:, None] * 0.5 + np.arange(n, dtype=np.float32)[None, :])
        hf = terracast.HeightField.from_array(heights, cell_size=1.0)
        del heights
        with open("/proc/self/clear_refs", "w") as f:
            f.write("5")
        before = status("VmRSS")
        m = hf.horizon(0.0, max_distance=20.0)
        print(status("VmHWM") - before, m.nbytes / 2**20)
    """)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=os.environ)
    assert out.returncode == 0, out.stderr
    grown, result = map(float, out.stdout.split())
    assert result == 61.03515625
    assert grown < 1.3 * result, (grown, result)
