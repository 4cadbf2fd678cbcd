#pragma once
// Images to numpy arrays and back, for the Python module (python/module.cpp).

#include "core/image.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

namespace sylva::python {

// One (height, width) float32 array per channel, keyed by its name. The arrays are views into the
// image's interleaved pixels (strides of one pixel and one row): no copy; the image lives as long
// as any of them.
pybind11::dict image_arrays(Image&& image);
// The image's string header attributes.
pybind11::dict image_header(const Image& image);
// Arrays of one shape (height, width), keyed by channel name, as an image (copied, as float).
Image arrays_image(const pybind11::dict& arrays);

void register_render(pybind11::module_& m);
void register_sensor(pybind11::module_& m);
void register_tools(pybind11::module_& m);

}  // namespace sylva::python
