# shellcheck shell=bash
# Writes a tiny detection study into folder $1 (study.toml over scene.toml: a vehicle on a plane,
# 6 frames of a Latin hypercube over range, aspect and sun elevation at 32 x 24, 2 spp); sourced by
# the MPI and Slurm study tests.
write_tiny_study() {
  cat >"$1/scene.toml" <<'TOML'
[render]
width = 32
height = 24
spp = 2
bands = ["rgb", "nir"]
max_depth = 3
[camera]
position = [0.0, -20.0, 3.0]
target = [0.0, 0.0, 1.0]
[sun]
azimuth = 150
elevation = 40
[materials.grey]
reflectance = 0.3
[materials.camo]
reflectance = 0.1
[[meshes]]
name = "ground"
shape = "plane"
size = [200, 200]
material = "grey"
class = "terrain"
[[targets]]
name = "tank"
file = "targets/vehicle.obj"
material = "camo"
label = "vehicle"
position = [0, 0, 0]
heading = 30
TOML
  cat >"$1/study.toml" <<'TOML'
[study]
scene = "scene.toml"
output = "out"
design = "latin_hypercube"
samples = 6
seed = 3
png = true
[[factors]]
name = "sun_elevation"
set = "sun.elevation"
range = [15, 70]
[[factors]]
name = "range_m"
range = [12, 40]
[[factors]]
name = "aspect_deg"
range = [0, 360]
[camera_orbit]
target = "tank"
range = "range_m"
aspect = "aspect_deg"
elevation = 5
aim_height = 1.2
TOML
}
