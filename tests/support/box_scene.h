#pragma once
// The text of a small scene file for tests that load or render scene text: a grey box on a grey
// plane under the sun, 24×16 pixels at 4 samples per pixel, bands rgb and nir.

namespace sylva::test {

inline constexpr const char* kBoxSceneToml = R"([render]
width = 24
height = 16
spp = 4
bands = ["rgb", "nir"]
max_depth = 4

[camera]
position = [0.0, -6.0, 4.0]
target = [0.0, 0.0, 0.0]

[sun]
azimuth = 210
elevation = 35

[materials.grey]
reflectance = 0.4

[[meshes]]
shape = "plane"
size = [40, 40]
material = "grey"

[[meshes]]
shape = "box"
size = [1.0, 1.0, 1.2]
material = "grey"
)";

}  // namespace sylva::test
