#!/usr/bin/env bash
# `cmake --install` into a throw-away prefix, then the installed programs run from a directory
# outside the source and build trees: `sylva render` with no arguments renders the built-in scene
# to ./sylva.exr and ./sylva.png; a scene there naming a mesh only the installed data holds renders
# (so the installed data is the one in use), and fails once that data is moved away; the docs,
# the OCIO config, the OpenImageIO module and the Python module are installed.
# Usage: install_prefix.sh CMAKE BUILD_DIR
set -euo pipefail
cmake=$1 build=$(cd "$2" && pwd)
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
prefix="$dir/prefix"
"$cmake" --install "$build" --prefix "$prefix" >"$dir/install.log"
fail=0
expect_file() {
  if [[ -f "$prefix/$1" ]]; then echo "ok: $1"; else echo "FAIL: $1 not installed"; fail=1; fi
}
expect_file bin/sylva
expect_file bin/libsylva_oiio.so
expect_file share/sylva/data/cie1931_2deg_cmf_1nm.csv
expect_file share/sylva/data/ocio/config.ocio
expect_file share/sylva/data/examples/objects.toml
expect_file share/sylva/data/species/quaking_aspen.toml
expect_file share/doc/sylva/README.md
expect_file share/doc/sylva/design.md
expect_file share/doc/sylva/scene_format.md
if grep -q sylva-mpi "$dir/install.log"; then expect_file bin/sylva-mpi; fi

# Outside both trees, with no data directory named in the environment.
work="$dir/elsewhere"
mkdir -p "$work"
cd "$work"
run() { env -u SYLVA_DATA_DIR -u SYLVA_DATA "$prefix/bin/sylva" "$@"; }
run render --res 48x27 --spp 1 --threads 2 --quiet
if [[ -s sylva.exr && -s sylva.png ]]; then echo "ok: sylva render (no scene) wrote sylva.exr and sylva.png"; else
  echo "FAIL: sylva render with no scene wrote no sylva.exr and sylva.png"; fail=1
fi
# A scene here naming a mesh only the installed tree holds, found through data_dir().
cp "$prefix/share/sylva/data/targets/vehicle.obj" "$prefix/share/sylva/data/targets/only_installed.obj"
cat >scene.toml <<'TOML'
[render]
width = 24
height = 16
spp = 1
[camera]
position = [0.0, -12.0, 3.0]
target = [0.0, 0.0, 1.0]
[materials.grey]
reflectance = 0.3
[[meshes]]
name = "ground"
shape = "plane"
size = [50, 50]
material = "grey"
[[targets]]
name = "car"
file = "targets/only_installed.obj"
material = "grey"
label = "vehicle"
position = [0, 0, 0]
TOML
run render scene.toml --threads 2 --quiet -o installed.exr --png installed.png
if [[ -s installed.exr && -s installed.png ]]; then echo "ok: a mesh of the installed data was found"; else
  echo "FAIL: the installed data is not where the installed sylva looks"; fail=1
fi
# The installed Python module (when the build made one), from here, by PYTHONPATH: it is the
# installed copy, it finds the installed data beside it (the mesh only that data holds) and renders.
if [[ -f "$build/python/sylva/__init__.py" ]]; then
  module=$(find "$prefix/lib" -path '*/dist-packages/sylva/__init__.py' -printf '%h\n' | head -1)
  if [[ -z $module ]]; then
    echo "FAIL: the Python module was built but not installed"; fail=1
  elif [[ ! -f $module/libsylva_oiio.so ]]; then
    echo "FAIL: the OpenImageIO module is not installed beside the Python module"; fail=1
  elif env -u SYLVA_DATA_DIR -u SYLVA_DATA PYTHONPATH="$(dirname "$module")" /usr/bin/python3 -c '
import os, sys, sylva
assert sylva.__file__.startswith(sys.argv[1]), sylva.__file__
assert os.environ["SYLVA_DATA_DIR"] == sys.argv[2], os.environ["SYLVA_DATA_DIR"]
image = sylva.render("scene.toml", threads=2)
assert image["R"].shape == (16, 24) and image["id.object"].max() > 0, sorted(image)' \
      "$module" "$(cd "$prefix/share/sylva/data" && pwd -P)"; then
    echo "ok: the installed Python module ($module) renders the installed mesh"
  else
    echo "FAIL: the installed Python module"; fail=1
  fi
fi
# The installed data is what it reads: without it, the same command fails.
mv "$prefix/share/sylva/data" "$prefix/share/sylva/moved"
if run render scene.toml --threads 2 --quiet -o again.exr 2>"$dir/err.txt"; then
  echo "FAIL: found the installed mesh after the installed data was moved away"; fail=1
elif grep -q "only_installed.obj" "$dir/err.txt"; then
  echo "ok: without its installed data the installed sylva does not find the mesh: $(head -1 "$dir/err.txt")"
else
  echo "FAIL: expected an error naming the mesh, got: $(cat "$dir/err.txt")"; fail=1
fi
exit $fail
