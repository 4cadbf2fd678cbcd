// `import sylva` (docs/python.md): the compiled part, `sylva._sylva`. Each function is a thin layer
// over the library's calls — the render call (pipeline/render_call.h), the sensor stage, the plot
// sensor, the tree generators and the study runner — with numpy arrays in and out. The pure-Python
// part (sylva/__init__.py) turns dicts into scene text and keyword arguments into these calls.
//
// Rendering releases the GIL; the progress callback takes it back for each report. Ctrl-C: while
// renders run (in any thread), SIGINT sets each one's cancel flag (Python's handler is restored
// when the last ends), they stop within 50 ms and each raises KeyboardInterrupt. sylva::Error (and ParseError, whose
// message starts with `file:line:`) becomes sylva.Error.

#include "python/arrays.h"

#include "core/error.h"
#include "pipeline/render_call.h"

#include <pybind11/functional.h>
#include <pybind11/stl.h>

#include <array>
#include <atomic>
#include <csignal>
#include <exception>
#include <mutex>
#include <string>
#include <vector>

namespace py = pybind11;

namespace sylva::python {

namespace {

// The cancel flags of the renders in progress (any thread), set by SIGINT: a lock-free table, so
// the handler only loads and stores atomics.
constexpr size_t kMaxRenders = 64;
std::array<std::atomic<std::atomic<bool>*>, kMaxRenders> g_active{};

extern "C" void on_sigint(int /*signal*/) {
  for (auto& slot : g_active)
    if (std::atomic<bool>* flag = slot.load()) flag->store(true);
}

// While alive, SIGINT sets `flag`. The first guard installs the handler and the last one restores
// the previous (Python's), so renders in several threads nest in any order.
class SigintGuard {
 public:
  explicit SigintGuard(std::atomic<bool>& flag) {
    for (slot_ = 0; slot_ < kMaxRenders; ++slot_) {
      std::atomic<bool>* empty = nullptr;
      if (g_active[slot_].compare_exchange_strong(empty, &flag)) break;
    }
    if (slot_ == kMaxRenders) throw Error("more than 64 renders at once");
    const std::lock_guard<std::mutex> lock(mutex_);
    if (users_++ == 0) {
      struct sigaction action {};
      action.sa_handler = on_sigint;
      sigemptyset(&action.sa_mask);
      sigaction(SIGINT, &action, &previous_);
    }
  }
  ~SigintGuard() {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (--users_ == 0) sigaction(SIGINT, &previous_, nullptr);
    g_active[slot_].store(nullptr);
  }
  SigintGuard(const SigintGuard&) = delete;
  SigintGuard& operator=(const SigintGuard&) = delete;

 private:
  size_t slot_ = 0;
  static inline std::mutex mutex_;
  static inline int users_ = 0;
  static inline struct sigaction previous_ {};
};

// Progress to a Python callable (done, total); cancelled by SIGINT or by the callable raising.
class PythonObserver : public RenderObserver {
 public:
  explicit PythonObserver(py::object progress) : progress_(std::move(progress)) {}

  void on_progress(const ProgressReport& report) override {
    if (progress_.is_none()) return;
    const std::lock_guard<std::mutex> lock(mutex_);
    if (error_) return;
    const py::gil_scoped_acquire gil;
    try {
      progress_(report.done, report.total);
    } catch (py::error_already_set&) {
      error_ = std::current_exception();
      cancel_.store(true);
    }
  }
  const std::atomic<bool>& cancel_flag() const override { return cancel_; }
  std::atomic<bool>& flag() { return cancel_; }
  std::exception_ptr error() const { return error_; }

 private:
  py::object progress_;
  std::mutex mutex_;
  std::exception_ptr error_;
  std::atomic<bool> cancel_{false};
};

struct RenderArgs {
  std::string scene_file, scene_text, scene_name;
  std::vector<std::string> overrides;
  std::string res, bands, quantity, exr, png;
  int spp = 0, threads = 0;
  int64_t seed = -1;
};

py::tuple render(const RenderArgs& a, const py::object& progress) {
  RenderCallOptions options;
  RenderRequest& r = options.request;
  if (!a.scene_file.empty()) r.source = SceneSource::from_file(a.scene_file);
  if (!a.scene_text.empty()) r.source = SceneSource::from_text(a.scene_text, a.scene_name);
  r.overrides = a.overrides;
  r.res = a.res;
  r.spp = a.spp;
  r.seed = a.seed;
  r.bands = a.bands;
  r.quantity = a.quantity;
  r.threads = a.threads;
  options.exr = a.exr;
  options.png = a.png;
  PythonObserver observer(progress);
  RenderResult result;
  {
    const SigintGuard sigint(observer.flag());
    const py::gil_scoped_release release;
    result = render_scene(options, observer);
  }
  if (observer.error()) std::rethrow_exception(observer.error());
  if (result.status != RenderStatus::finished) {
    PyErr_SetString(
        PyExc_KeyboardInterrupt,
        result.outputs.checkpoint.empty()
            ? "render interrupted"
            : ("render interrupted; the samples are kept in " + result.outputs.checkpoint.string()).c_str());
    throw py::error_already_set();
  }
  py::dict sensor;
  if (!result.sensor.pixels.empty()) sensor = image_arrays(std::move(result.sensor));
  py::dict header = image_header(result.image);
  return py::make_tuple(image_arrays(std::move(result.image)), header, sensor);
}

py::tuple read_exr_arrays(const std::string& path) {
  Image image = read_exr(path);
  py::dict header = image_header(image);
  return py::make_tuple(image_arrays(std::move(image)), header);
}

}  // namespace

void register_render(py::module_& m) {
  py::class_<RenderArgs>(m, "RenderArgs")
      .def(py::init<>())
      .def_readwrite("scene_file", &RenderArgs::scene_file)
      .def_readwrite("scene_text", &RenderArgs::scene_text)
      .def_readwrite("scene_name", &RenderArgs::scene_name)
      .def_readwrite("overrides", &RenderArgs::overrides)
      .def_readwrite("res", &RenderArgs::res)
      .def_readwrite("bands", &RenderArgs::bands)
      .def_readwrite("quantity", &RenderArgs::quantity)
      .def_readwrite("exr", &RenderArgs::exr)
      .def_readwrite("png", &RenderArgs::png)
      .def_readwrite("spp", &RenderArgs::spp)
      .def_readwrite("threads", &RenderArgs::threads)
      .def_readwrite("seed", &RenderArgs::seed);
  m.def("render", &render, py::arg("args"), py::arg("progress") = py::none(),
        "Render a scene: (channels, header, sensor channels), arrays without copies");
  m.def("read_exr", &read_exr_arrays, py::arg("path"), "An EXR's channels and string header");
}

}  // namespace sylva::python

PYBIND11_MODULE(_sylva, m) {
  m.doc() = "Sylva, a spectral forest path tracer (docs/python.md)";
  py::register_exception<sylva::Error>(m, "Error", PyExc_RuntimeError);
  sylva::python::register_render(m);
  sylva::python::register_sensor(m);
  sylva::python::register_tools(m);
}
