#include "python/arrays.h"

#include "core/error.h"

#include <memory>
#include <string>

namespace py = pybind11;

namespace sylva::python {

py::dict image_arrays(Image&& image) {
  auto* owned = new Image(std::move(image));
  const py::capsule keep(owned, [](void* p) { delete static_cast<Image*>(p); });
  py::dict out;
  const auto c = static_cast<py::ssize_t>(owned->channel_count());
  const py::ssize_t f = sizeof(float);
  for (py::ssize_t i = 0; i < c; ++i) {
    float* first = owned->pixels.data() + i;
    out[py::str(owned->channels[static_cast<size_t>(i)])] =
        py::array_t<float>({static_cast<py::ssize_t>(owned->height), static_cast<py::ssize_t>(owned->width)},
                           {owned->width * c * f, c * f}, first, keep);
  }
  return out;
}

py::dict image_header(const Image& image) {
  py::dict header;
  for (const auto& [key, value] : image.attributes) header[py::str(key)] = py::str(value);
  return header;
}

Image arrays_image(const py::dict& arrays) {
  Image image;
  std::vector<py::array_t<float, py::array::c_style | py::array::forcecast>> planes;
  for (const auto& [key, value] : arrays) {
    auto a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(value);
    if (!a || a.ndim() != 2) throw Error("channel " + py::str(key).cast<std::string>() + ": expected a 2-D array");
    if (planes.empty()) {
      image.height = static_cast<int>(a.shape(0));
      image.width = static_cast<int>(a.shape(1));
    } else if (a.shape(0) != image.height || a.shape(1) != image.width) {
      throw Error("channel " + py::str(key).cast<std::string>() + ": expected the shape of the first channel");
    }
    image.channels.push_back(py::str(key).cast<std::string>());
    planes.push_back(std::move(a));
  }
  if (planes.empty()) throw Error("no channels given");
  image = make_image(image.width, image.height, image.channels);
  const size_t n = planes.size();
  for (size_t c = 0; c < n; ++c) {
    const float* src = planes[c].data();
    for (size_t i = 0; i < static_cast<size_t>(image.width) * image.height; ++i) image.pixels[i * n + c] = src[i];
  }
  return image;
}

}  // namespace sylva::python
