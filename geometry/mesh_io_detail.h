#pragma once
// Internals shared by mesh_io.cpp, obj_reader.cpp and ply_reader.cpp. Not part of the API.

#include "geometry/mesh.h"

#include <filesystem>
#include <string>
#include <string_view>

namespace sylva::mesh_io_detail {

// Parses the whole file content; `file` is only used in error messages.
TriangleMesh parse_obj(const std::filesystem::path& file, std::string_view text);
TriangleMesh parse_ply(const std::filesystem::path& file, std::string_view bytes);

// A short, printable rendering of untrusted text for error messages.
std::string printable(std::string_view s);

}  // namespace sylva::mesh_io_detail
