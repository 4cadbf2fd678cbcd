"""`import sylva` (docs/python.md), run by ctest (python_module): renders equal the CLI's bit for bit,
arrays are views, dict scenes and overrides, errors with file:line, progress, Ctrl-C, the GIL
released, the sensor on arrays, tree meshes and a study.

Monte Carlo results are compared by z-tests on the image mean, its standard error from the film's
`var.<C>` (the variance of each pixel mean; pixels are independent), never by a fixed value."""

import json
import os
import pathlib
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import sylva

SYLVA = os.environ.get("SYLVA_BINARY", "sylva")
SOURCE = pathlib.Path(__file__).resolve().parents[2]

BOX = {
    "render": {"width": 24, "height": 16, "spp": 4, "bands": ["rgb", "nir"], "max_depth": 4},
    "camera": {"position": [0.0, -6.0, 4.0], "target": [0.0, 0.0, 0.0]},
    "sun": {"azimuth": 210, "elevation": 35},
    "materials": {"grey": {"reflectance": 0.4}},
    "meshes": [{"shape": "plane", "size": [40, 40], "material": "grey"},
               {"shape": "box", "size": [1.0, 1.0, 1.2], "material": "grey"}],
}


def mean_and_se(image, channel):
    """The image mean of a channel and its standard error from var.<channel>."""
    values = image[channel].astype(np.float64)
    return values.mean(), np.sqrt(image["var." + channel].astype(np.float64).sum()) / values.size


@pytest.fixture
def box_file(tmp_path):
    path = tmp_path / "box.toml"
    path.write_text(sylva.to_toml(BOX))
    return path


def test_render_is_bit_identical_to_the_cli(tmp_path, box_file):
    cli = tmp_path / "cli.exr"
    subprocess.run([SYLVA, "render", str(box_file), "--res", "24x16", "--spp", "4", "--seed", "3", "--threads", "2",
                    "-q", "-o", str(cli)], check=True)
    from_cli, header = sylva.read_exr(cli)
    image = sylva.render(box_file, res=(24, 16), spp=4, seed=3, threads=2)
    compared = 0
    for name in ("R", "G", "B", "nir.Y", "var.R", "var.nir.Y"):
        assert name in image, sorted(image)
        assert np.array_equal(image[name], from_cli[name]), name
        compared += 1
    assert compared == 6
    assert image["R"].shape == (16, 24) and image["R"].dtype == np.float32
    assert float(image["R"].mean()) > 0


def test_arrays_are_views_of_one_buffer(box_file):
    image = sylva.render(box_file, spp=1)
    r = image["R"]
    assert not r.flags.owndata and r.base is not None
    channels = len(image)
    assert r.strides == (24 * channels * 4, channels * 4)
    assert image["G"].__array_interface__["data"][0] - r.__array_interface__["data"][0] == 4


def test_dict_scene_equals_its_file_and_overrides_apply(box_file):
    from_dict = sylva.render(BOX, spp=2, seed=5)
    from_file = sylva.render(box_file, spp=2, seed=5)
    assert np.array_equal(from_dict["R"], from_file["R"])
    same = sylva.render(BOX, spp=2, seed=5, overrides=["sun.elevation=8"])
    low_sun = sylva.render(BOX, spp=2, seed=5, overrides={"sun.elevation": 8})
    assert np.array_equal(same["R"], low_sun["R"])
    # The sun at 8° instead of 35° lights the grey ground with sin 8°/sin 35° = 0.24 of the direct
    # irradiance; with the sky's share the image mean falls below 0.8 of it (one-sided z > 4).
    high, high_se = mean_and_se(from_dict, "R")
    low, low_se = mean_and_se(low_sun, "R")
    assert (0.8 * high - low) / np.hypot(0.8 * high_se, low_se) > 4


def test_another_seed_agrees_within_the_reported_variance():
    a, a_se = mean_and_se(sylva.render(BOX, spp=2, seed=5), "R")
    b, b_se = mean_and_se(sylva.render(BOX, spp=2, seed=6), "R")
    assert a != b
    assert abs(a - b) / np.hypot(a_se, b_se) < 4  # two-sided, alpha = 6e-5


def test_bad_input_is_a_clear_error(tmp_path):
    with pytest.raises(sylva.Error, match=r"missing\.toml"):
        sylva.render(tmp_path / "missing.toml")
    with pytest.raises(sylva.Error, match=r"--res"):
        sylva.render(BOX, res="12by4")
    with pytest.raises(sylva.Error, match="cannot write object"):
        sylva.render({"sun": {"elevation": object()}})
    with pytest.raises(sylva.Error, match="expected a 2-D array"):
        sylva.apply_sensor({"G": np.zeros(4, np.float32)}, "phone_8bit")
    with pytest.raises(sylva.Error, match="no such file"):
        sylva.read_exr(tmp_path / "missing.exr")


def test_errors_carry_file_and_line(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("[render]\nwidth = 24\n\n[sun]\nelevaton = 10\n")
    with pytest.raises(sylva.Error, match=r"bad\.toml:5: unknown key 'elevaton' in \[sun\]"):
        sylva.render(bad)
    with pytest.raises(sylva.Error, match=r"--set sun\.elevaton=10: unknown key 'elevaton'"):
        sylva.render(BOX, overrides={"sun.elevaton": 10})
    assert issubclass(sylva.Error, RuntimeError)


def test_progress_is_reported(box_file):
    seen = []
    sylva.render(box_file, res=(48, 32), spp=8, progress=lambda done, total: seen.append((done, total)))
    assert seen, "no progress reported"
    assert all(b[0] >= a[0] for a, b in zip(seen, seen[1:]))
    assert seen[-1][0] == seen[-1][1] == 48 * 32 * 8


def test_ctrl_c_interrupts_cleanly(box_file):
    # SIGINT from another thread 0.3 s in, as a Ctrl-C at the terminal; the whole render would take
    # minutes.
    timer = threading.Timer(0.3, os.kill, (os.getpid(), signal.SIGINT))
    start = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        sylva.render(box_file, res=(160, 120), spp=4096, threads=2)
    timer.join()
    assert time.monotonic() - start < 5
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler

    def interrupt(done, total):
        os.kill(os.getpid(), signal.SIGINT)

    with pytest.raises(KeyboardInterrupt):
        sylva.render(box_file, res=(160, 120), spp=4096, threads=2, progress=interrupt)
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
    assert sylva.render(box_file, spp=1)["R"].shape == (16, 24)


def test_ctrl_c_stops_the_renders_of_every_thread(box_file):
    interrupted = []
    rendering = [threading.Event(), threading.Event()]

    def work(started):
        try:
            sylva.render(box_file, res=(160, 120), spp=4096, threads=1, progress=lambda done, total: started.set())
        except KeyboardInterrupt:
            interrupted.append(True)

    threads = [threading.Thread(target=work, args=(started,)) for started in rendering]
    for thread in threads:
        thread.start()
    assert all(started.wait(60) for started in rendering)
    os.kill(os.getpid(), signal.SIGINT)
    for thread in threads:
        thread.join(timeout=10)
    assert interrupted == [True, True]
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


def test_rendering_releases_the_gil(box_file):
    # While another thread renders (about half a second), this one keeps running Python: with the
    # GIL held it would not run at all until the render returned.
    done = threading.Event()
    ticks = 0

    def work():
        sylva.render(box_file, res=(96, 64), spp=64, threads=1)
        done.set()

    thread = threading.Thread(target=work)
    start = time.monotonic()
    thread.start()
    while not done.is_set():
        ticks += 1
        done.wait(0.001)
    thread.join()
    elapsed = time.monotonic() - start
    assert elapsed > 0.05 and ticks > 10, f"the main thread ran {ticks} times in {elapsed:.2f} s of rendering"


def test_the_sensor_on_arrays():
    plate = {"G": np.full((64, 64), 0.02, np.float32)}
    sensed, header, sidecar = sylva.apply_sensor(plate, {"preset": "machine_vision_12bit", "oversample": 2},
                                                 noise_seed=4)
    assert sensed["G"].shape == (32, 32)
    assert header["sylva:sensor:noise_seed"] == "4"
    record = json.loads(sidecar)
    cal = record["calibration"][0]
    dn = sensed["G"].astype(np.float64)
    # The calibration recovers the plate's radiance: a z-test of the mean over 32x32 detectors,
    # its standard error from their spread (shot, read and fixed-pattern noise).
    radiance = cal["radiance_per_dn"] * (dn.mean() - cal["dn_offset"])
    se = cal["radiance_per_dn"] * dn.std() / np.sqrt(dn.size)
    assert abs(radiance - 0.02) < 4 * se
    again, _, _ = sylva.apply_sensor(plate, "machine_vision_12bit", noise_seed=4)
    assert np.array_equal(again["G"], sensed["G"])
    other, _, _ = sylva.apply_sensor(plate, "machine_vision_12bit", noise_seed=5)
    assert not np.array_equal(other["G"], sensed["G"])
    with pytest.raises(sylva.Error, match="unknown sensor preset 'nope'"):
        sylva.apply_sensor(plate, "nope")
    assert "phone_8bit" in sylva.sensor_presets()


def test_render_with_a_sensor_returns_its_channels(tmp_path):
    scene = dict(BOX, sensor={"preset": "phone_8bit"})
    image = sylva.render(scene, spp=2, exr=tmp_path / "s.exr")
    assert image["sensor.G"].shape == (8, 12)
    assert (tmp_path / "s.sensor.exr").is_file() and (tmp_path / "s.sensor.json").is_file()


def test_tree_mesh_as_arrays():
    mesh = sylva.tree_mesh(SOURCE / "data" / "species" / "quaking_aspen.toml", seed=2, quality=0.3)
    positions, triangles = mesh["positions"], mesh["triangles"]
    assert positions.ndim == 2 and positions.shape[1] == 3 and len(positions) > 100
    assert triangles.max() < len(positions)
    assert mesh["leaf_corners"].shape[0] % 4 == 0


PLOT = {
    "render": {"bands": ["S2A_B4", "S2A_B8"]},
    "sun": {"elevation": 60},
    "sky": {"model": "none"},
    "materials": {"leaf": {"type": "leaf", "reflectance": 0.45, "transmittance": 0.45},
                  "soil": {"reflectance": 0.2}},
    "plot": {"size": [4, 4], "cyclic": True, "principal_plane": [-40, 40, 20], "samples": 500,
             "flux_samples": 2000, "ground": ["soil"]},
    "meshes": [{"shape": "plane", "size": [4, 4], "material": "soil"}],
    "canopies": [{"type": "homogeneous", "lai": 1, "height": 1, "material": "leaf"}],
}


def test_the_plot_sensor_as_arrays(tmp_path):
    tables = sylva.measure(PLOT, threads=2)
    assert tables["brf_channels"] == ["S2A_B4.Y", "S2A_B8.Y"]
    assert tables["brf"].shape == tables["brf_se"].shape == (5, 2)
    assert list(tables["brf_views"][:, 0]) == [40, 20, 0, 20, 40]
    assert (tables["brf"] > 0).all() and (tables["brf_se"] > 0).all()
    terms = tables["flux_terms"]
    assert tables["flux"].shape == (2, len(terms))
    # A cyclic plot keeps energy: what is absorbed plus what leaves upwards is the incident light.
    total = tables["flux"][:, terms.index("absorbed_plus_reflected")]
    total_se = tables["flux_se"][:, terms.index("absorbed_plus_reflected")]
    assert (np.abs(total - 1) <= 4 * total_se + 1e-9).all(), (total, total_se)
    path = tmp_path / "plot.toml"
    path.write_text(sylva.to_toml(PLOT))
    from_file = sylva.measure(path, threads=1, flux_samples=-1)
    assert np.array_equal(from_file["brf"], tables["brf"]) and "flux" not in from_file


def test_a_study(tmp_path):
    (tmp_path / "scene.toml").write_text(sylva.to_toml(dict(BOX, render=dict(BOX["render"], spp=1))))
    (tmp_path / "study.toml").write_text(
        '[study]\nscene = "scene.toml"\noutput = "out"\ndesign = "grid"\n'
        '[[factors]]\nname = "elevation"\nset = "sun.elevation"\nvalues = [20, 60]\n')
    result = sylva.study(tmp_path / "study.toml")
    assert result["frames"] == 2 and result["rendered"] == 2 and result["finished"]
    assert pathlib.Path(result["manifest_csv"]).is_file()


def test_the_sweep_example_runs(tmp_path):
    out = tmp_path / "sweep.png"
    subprocess.run([sys.executable, str(SOURCE / "python" / "examples" / "sun_sweep.py"), "--scene",
                    str(SOURCE / "data" / "examples" / "objects.toml"), "--res", "32x18", "--spp", "1", "--out",
                    str(out)], check=True, env=dict(os.environ))
    assert out.stat().st_size > 1000
