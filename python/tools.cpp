// The Python module's other calls: the sensor model on arrays, a tree's mesh, the plot sensor's
// tables and a study (python/module.cpp has the render call).

#include "python/arrays.h"

#include "core/band.h"
#include "core/error.h"
#include "pipeline/measure.h"
#include "pipeline/study.h"
#include "pipeline/study_design.h"
#include "scenes/species.h"
#include "scenes/toml_reader.h"
#include "sensor/presets.h"
#include "sensor/sensor.h"

#include <pybind11/stl.h>

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <string>
#include <tuple>
#include <vector>

namespace py = pybind11;

namespace sylva::python {

namespace {

// The [sensor] table of `toml` (a scene fragment) read as the scene parser reads it.
SensorParams sensor_params_of(const std::string& toml, const std::string& name) {
  const TomlReader reader(name);
  const toml::table document = reader.parse(toml);
  const toml::table* t = reader.table(document, "sensor");
  if (t == nullptr) return {};
  const FileResolver resolver = [](const std::string& file) { return find_named_file({}, file); };
  return read_sensor_params(reader.to_params(*t, "[sensor]", resolver));
}

// A channel: a band channel by name ("R", "nir.Y" of a known band), or (name, centre_nm, width_nm).
std::vector<SensorChannel> channels_of(const py::dict& arrays, const py::dict& wavelengths) {
  std::vector<SensorChannel> out;
  for (const auto& [key, value] : arrays) {
    const std::string name = py::str(key).cast<std::string>();
    if (wavelengths.contains(key)) {
      const auto [centre, width] = wavelengths[key].cast<std::pair<double, double>>();
      out.push_back(monochromatic_channel(name, centre, width));
      continue;
    }
    const std::string band = name == "R" || name == "G" || name == "B" ? "rgb" : name.substr(0, name.rfind('.'));
    Band b;
    try {
      b = resolve_band(band);
    } catch (const Error& e) {
      throw Error("channel " + name + ": not a band channel (" + e.what() +
                  "); give its wavelengths={name: (centre_nm, width_nm)}");
    }
    bool found = false;
    for (size_t c = 0; c < b.channels.size(); ++c)
      if (b.channels[c] == name) out.push_back(describe_channel(name, band, b.weights[c])), found = true;
    if (!found) throw Error("channel " + name + ": not a band channel; give its wavelengths (centre_nm, width_nm)");
  }
  return out;
}

py::tuple apply_sensor_arrays(const py::dict& arrays, const std::string& sensor_toml, const py::dict& wavelengths,
                              double render_pixel_rad, double distance_m, uint64_t noise_seed) {
  const Image image = arrays_image(arrays);
  const SensorParams params = sensor_params_of(sensor_toml, "<sensor>");
  const std::vector<SensorChannel> channels = channels_of(arrays, wavelengths);
  SensedImage sensed;
  {
    py::gil_scoped_release release;
    sensed = apply_sensor(image, channels, params, {render_pixel_rad, distance_m}, noise_seed);
  }
  py::dict header = image_header(sensed.image);
  return py::make_tuple(image_arrays(std::move(sensed.image)), header, sensor_json(sensed, params));
}

template <typename T>
py::array_t<T> flat_array(const T* data, size_t rows, size_t cols) {
  py::array_t<T> a({static_cast<py::ssize_t>(rows), static_cast<py::ssize_t>(cols)});
  std::copy(data, data + rows * cols, a.mutable_data());
  return a;
}

py::dict tree_mesh(const std::string& species_file, uint64_t seed, double quality) {
  const Species species = load_species(species_file);
  TreeOptions options;
  options.quality = static_cast<float>(quality);
  TreeMesh mesh;
  {
    py::gil_scoped_release release;
    const TreeModel model = make_species_model(species, seed, options);
    TreeMeshOptions mesh_options;
    mesh_options.quality = options.quality;
    mesh = mesh_species_model(species, model, mesh_options);
  }
  py::dict out;
  const TriangleMesh& s = mesh.stems;
  out["positions"] = flat_array(&s.positions.data()->x, s.positions.size(), 3);
  out["normals"] = flat_array(&s.normals.data()->x, s.normals.size(), 3);
  out["triangles"] = flat_array(&s.triangles.data()->x, s.triangles.size(), 3);
  out["leaf_corners"] = flat_array(&mesh.leaves.corners.data()->x, mesh.leaves.corners.size(), 3);
  return out;
}

py::dict measure_arrays(const std::string& scene_file, const std::string& scene_text,
                        const std::vector<std::string>& overrides, int samples, int flux_samples, int threads) {
  MeasureCallOptions options;
  options.request.source =
      scene_text.empty() ? SceneSource::from_file(scene_file) : SceneSource::from_text(scene_text, "<scene dict>");
  options.request.overrides = overrides;
  options.request.threads = threads;
  options.samples = samples;
  options.flux_samples = std::max(0, flux_samples);
  // The call writes its tables as CSV; they go to a temporary folder of this call and are returned
  // as arrays.
  static std::atomic<uint64_t> calls{0};
  const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                    ("sylva_measure_" + std::to_string(::getpid()) + "_" + std::to_string(calls++));
  std::filesystem::create_directories(dir);
  options.brf = dir / "brf.csv";
  options.flux = flux_samples >= 0 ? dir / "flux.csv" : std::filesystem::path();
  RenderObserver observer;
  MeasureResult r;
  try {
    py::gil_scoped_release release;
    r = measure_scene(options, observer);
  } catch (...) {
    std::filesystem::remove_all(dir);
    throw;
  }
  std::filesystem::remove_all(dir);
  py::dict out;
  if (r.brf) {
    const BrfTable& t = *r.brf;
    py::array_t<double> mean({t.views.size(), t.channels.size()}), se({t.views.size(), t.channels.size()});
    py::array_t<double> views({t.views.size(), size_t{2}});
    for (size_t v = 0; v < t.views.size(); ++v) {
      views.mutable_at(v, 0) = t.views[v].zenith_deg;
      views.mutable_at(v, 1) = t.views[v].azimuth_deg;
      for (size_t c = 0; c < t.channels.size(); ++c)
        mean.mutable_at(v, c) = t.mean[v][c], se.mutable_at(v, c) = t.se[v][c];
    }
    out["brf_channels"] = t.channels;
    out["brf_views"] = views;
    out["brf"] = mean;
    out["brf_se"] = se;
  }
  if (r.flux) {
    const FluxTable& t = *r.flux;
    py::array_t<double> mean({t.channels.size(), size_t{FluxTable::kTerms}}), se(mean.request().shape);
    for (size_t c = 0; c < t.channels.size(); ++c)
      for (size_t k = 0; k < FluxTable::kTerms; ++k)
        mean.mutable_at(c, k) = t.mean[c][k], se.mutable_at(c, k) = t.se[c][k];
    out["flux_channels"] = t.channels;
    out["flux_terms"] = std::vector<std::string>(FluxTable::kNames, FluxTable::kNames + FluxTable::kTerms);
    out["flux"] = mean;
    out["flux_se"] = se;
  }
  return out;
}

py::dict run_study_file(const std::string& study_file, const std::string& output_dir, int shard_index, int shard_count,
                        int threads) {
  const StudySpec spec = load_study(study_file);
  StudyRunOptions options;
  options.output_dir = output_dir;
  options.shard_index = shard_index;
  options.shard_count = shard_count;
  options.threads = threads;
  RenderObserver observer;
  StudyResult r;
  {
    py::gil_scoped_release release;
    r = run_study(spec, options, observer);
  }
  py::dict out;
  out["output_dir"] = r.output_dir.string();
  out["manifest_csv"] = r.manifest_csv.string();
  out["manifest_json"] = r.manifest_json.string();
  out["frames"] = r.frames.size();
  out["rendered"] = r.rendered;
  out["skipped"] = r.skipped;
  out["finished"] = r.status == RenderStatus::finished;
  return out;
}

}  // namespace

void register_sensor(py::module_& m) {
  m.def("apply_sensor", &apply_sensor_arrays, py::arg("arrays"), py::arg("sensor_toml"), py::arg("wavelengths"),
        py::arg("render_pixel_rad"), py::arg("distance_m"), py::arg("noise_seed"),
        "The sensor model on arrays: (channels, header, sidecar JSON)");
  m.def("sensor_presets", [] {
    py::dict out;
    for (const SensorPreset& p : sensor_presets()) out[py::str(p.name)] = p.source;
    return out;
  });
}

void register_tools(py::module_& m) {
  m.def("tree_mesh", &tree_mesh, py::arg("species"), py::arg("seed"), py::arg("quality"));
  m.def("measure", &measure_arrays, py::arg("scene_file"), py::arg("scene_text"), py::arg("overrides"),
        py::arg("samples"), py::arg("flux_samples"), py::arg("threads"));
  m.def("study", &run_study_file, py::arg("study"), py::arg("output_dir"), py::arg("shard_index"),
        py::arg("shard_count"), py::arg("threads"));
}

}  // namespace sylva::python
