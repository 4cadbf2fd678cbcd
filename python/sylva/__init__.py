"""Sylva from Python (docs/python.md).

    import sylva
    image = sylva.render("scene.toml", res=(320, 180), spp=16, overrides={"sun.elevation": 30})
    image["R"]          # a (height, width) float32 numpy array, a view without a copy

Scenes are files, TOML text or dicts (the scene file's tables as nested dicts); overrides are the
command line's `--set` (a dict or a list of "KEY=VALUE"). Errors are `sylva.Error` with the
`file:line:` of the mistake. Rendering releases the GIL; Ctrl-C stops it and raises
KeyboardInterrupt.
"""

import math
import os
import pathlib

# An installed module finds the installed data: <prefix>/lib/python3/dist-packages/sylva/ →
# <prefix>/share/sylva/data (unless SYLVA_DATA_DIR names one).
_installed_data = pathlib.Path(__file__).resolve().parents[4] / "share" / "sylva" / "data"
if not os.environ.get("SYLVA_DATA_DIR") and (_installed_data / "cie1931_2deg_cmf_1nm.csv").is_file():
    os.environ["SYLVA_DATA_DIR"] = str(_installed_data)

from . import _sylva  # noqa: E402
from ._sylva import Error, read_exr as _read_exr  # noqa: E402

__all__ = ["Error", "render", "render_with_header", "read_exr", "to_toml", "apply_sensor", "sensor_presets",
           "tree_mesh", "measure", "study"]


def _toml_value(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if not math.isfinite(v):
            raise Error(f"{v}: TOML has no such number here")
        return repr(v)
    if isinstance(v, (str, os.PathLike)):
        s = str(v).replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n")
        return f'"{s}"'
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{_toml_key(k)} = {_toml_value(x)}" for k, x in v.items()) + " }"
    if hasattr(v, "tolist"):  # numpy arrays and scalars
        return _toml_value(v.tolist())
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    raise Error(f"cannot write {type(v).__name__} {v!r} as a scene value")


def _toml_key(k):
    k = str(k)
    return k if k and all(c.isalnum() or c in "_-" for c in k) else _toml_value(k)


def _is_table_array(v):
    return isinstance(v, (list, tuple)) and len(v) > 0 and all(isinstance(x, dict) for x in v)


def _toml_table(name, table, lines):
    scalars = [(k, v) for k, v in table.items() if not isinstance(v, dict) and not _is_table_array(v)]
    if name and (scalars or not table):
        lines.append(f"[{name}]")
    for k, v in scalars:
        lines.append(f"{_toml_key(k)} = {_toml_value(v)}")
    for k, v in table.items():
        path = f"{name}.{_toml_key(k)}" if name else _toml_key(k)
        if isinstance(v, dict):
            _toml_table(path, v, lines)
        elif _is_table_array(v):
            for entry in v:
                lines.append(f"[[{path}]]")
                for ek, ev in entry.items():
                    lines.append(f"{_toml_key(ek)} = {_toml_value(ev)}")


def to_toml(scene):
    """A scene dict as scene-file text (tables, arrays of tables, inline tables inside them)."""
    lines = []
    _toml_table("", scene, lines)
    return "\n".join(lines) + "\n"


def _overrides(overrides):
    if overrides is None:
        return []
    if isinstance(overrides, dict):
        return [f"{k}={_toml_value(v)}" for k, v in overrides.items()]
    return [str(o) for o in overrides]


def _render_args(scene, overrides, res, spp, seed, bands, threads, quantity, exr, png):
    a = _sylva.RenderArgs()
    if isinstance(scene, dict):
        a.scene_text = to_toml(scene)
        a.scene_name = "<scene dict>"
    elif scene is not None:
        a.scene_file = os.fspath(scene)
    a.overrides = _overrides(overrides)
    if res is not None:
        a.res = res if isinstance(res, str) else f"{int(res[0])}x{int(res[1])}"
    a.spp = int(spp or 0)
    a.seed = -1 if seed is None else int(seed)
    if bands is not None:
        a.bands = bands if isinstance(bands, str) else ",".join(bands)
    a.threads = int(threads or 0)
    a.quantity = quantity or ""
    a.exr = os.fspath(exr) if exr else ""
    a.png = os.fspath(png) if png else ""
    return a


def render_with_header(scene=None, *, overrides=None, res=None, spp=None, seed=None, bands=None, threads=0,
                       quantity=None, exr=None, png=None, progress=None):
    """Like render(), returning (channels, header, sensor channels); the last is empty without [sensor]."""
    args = _render_args(scene, overrides, res, spp, seed, bands, threads, quantity, exr, png)
    return _sylva.render(args, progress)


def render(scene=None, *, overrides=None, res=None, spp=None, seed=None, bands=None, threads=0, quantity=None,
           exr=None, png=None, progress=None):
    """Render a scene (None: the built-in default; a path; a dict) to {channel name: array}.

    The arrays are (height, width) float32 views of the film's channels ("R", "G", "B", "nir.Y",
    "var.R", "Z", "id.instance", ...). With [sensor] the sensed image's channels follow as
    "sensor.<C>" (detector grid). exr/png also write the usual files (and the sensor's beside
    them). progress(done, total) is called from the rendering thread with the GIL held.
    """
    channels, _, sensor = render_with_header(scene, overrides=overrides, res=res, spp=spp, seed=seed, bands=bands,
                                             threads=threads, quantity=quantity, exr=exr, png=png, progress=progress)
    for name, array in sensor.items():
        channels["sensor." + name] = array
    return channels


def read_exr(path):
    """An EXR's channels as arrays and its string header: (channels, header)."""
    return _read_exr(os.fspath(path))


def sensor_presets():
    """{preset name: the source of its figures}."""
    return _sylva.sensor_presets()


def apply_sensor(channels, sensor=None, *, wavelengths=None, render_pixel_rad=0.0, distance_m=0.0, noise_seed=1):
    """The sensor model (docs/sensors.md) on arrays of radiance: (sensed channels, header, sidecar JSON).

    channels: {name: (h, w) array}; band channels ("R", "nir.Y", "S2A_B8.Y") take their band's
    response, others need wavelengths={name: (centre_nm, equivalent_width_nm)}. sensor: a dict of
    [sensor] keys (e.g. {"preset": "phone_8bit", "read_noise_e": 4}) or a preset name.
    """
    if isinstance(sensor, str):
        sensor = {"preset": sensor}
    text = to_toml({"sensor": dict(sensor or {})})
    return _sylva.apply_sensor(dict(channels), text, dict(wavelengths or {}), float(render_pixel_rad),
                               float(distance_m), int(noise_seed))


def tree_mesh(species, seed=1, quality=1.0):
    """A tree of a species file as arrays: positions, normals, triangles (bark), leaf_corners (4 per leaf)."""
    return _sylva.tree_mesh(os.fspath(species), int(seed), float(quality))


def measure(scene, *, overrides=None, samples=0, flux_samples=0, threads=0):
    """The plot sensor (docs/radiometry.md) of a scene file or dict with a [plot]: BRF per view and
    the flux budget as arrays with standard errors.

    flux_samples < 0 skips the flux budget.
    """
    text = to_toml(scene) if isinstance(scene, dict) else ""
    path = "" if isinstance(scene, dict) else os.fspath(scene)
    return _sylva.measure(path, text, _overrides(overrides), int(samples), int(flux_samples), int(threads))


def study(study_file, output_dir="", *, shard=(0, 1), threads=0):
    """Run a detection study (docs/studies.md); returns its manifest paths and frame counts."""
    return _sylva.study(os.fspath(study_file), os.fspath(output_dir), int(shard[0]), int(shard[1]), int(threads))
