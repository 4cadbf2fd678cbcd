#include "pipeline/study_annotations.h"

#include "core/error.h"
#include "core/input_file.h"
#include "scenes/sidecar.h"
#include "scenes/view_metadata.h"

#include <fmt/core.h>

#include <algorithm>
#include <charconv>
#include <map>
#include <sstream>

namespace sylva {

namespace {

std::string one_line(std::string s) {
  std::replace(s.begin(), s.end(), '\n', ' ');
  return s;
}

std::string coco_box(const PixelBox& b) {
  return b.empty() ? "null" : fmt::format("[{}, {}, {}, {}]", b.x0, b.y0, b.width(), b.height());
}

std::string coco_annotation(const FrameAnnotationInput& in, const TargetAnnotation& a, size_t k) {
  const int w = in.image->width, h = in.image->height;
  std::string counts;
  for (const uint64_t c : rle_counts(a.modal, w, h)) counts += fmt::format("{}{}", counts.empty() ? "" : ",", c);
  return fmt::format(
      "{{\"id\": {}, \"image_id\": {}, \"category_id\": {}, \"bbox\": {}, \"amodal_bbox\": {}, \"truncated\": {}, "
      "\"area\": {}, \"iscrowd\": 0, \"segmentation\": {{\"size\": [{}, {}], \"counts\": [{}]}}, \"sylva_target\": {}, "
      "\"visible_pixels\": {}, \"unoccluded_pixels\": {}, \"visible_fraction\": {}, \"critical_dimension_px\": {}, "
      "\"characteristic_dimension_px\": {}}}",
      (in.frame_index + 1) * 65536 + k + 1, in.frame_index + 1, a.class_id, coco_box(a.modal_box),
      coco_box(a.amodal_box), a.truncated ? 1 : 0, a.visible_pixels, h, w, counts, json_string(a.name),
      a.visible_pixels, a.unoccluded_pixels, a.visible_fraction(), a.critical_dimension_px,
      a.characteristic_dimension_px);
}

std::string xml_text(const std::string& s) {
  std::string out;
  for (const char c : s) {
    if (c == '&')
      out += "&amp;";
    else if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '"')
      out += "&quot;";
    else
      out += c;
  }
  return out;
}

// The id of a category line `{"id": N, ...}` of a frame's COCO file.
int64_t category_id(const std::string& line, const std::filesystem::path& file) {
  const size_t colon = line.find(':');
  int64_t id = -1;
  const char* first = colon == std::string::npos ? line.data() + line.size() : line.data() + colon + 1;
  while (first < line.data() + line.size() && *first == ' ') ++first;
  const auto [ptr, ec] = std::from_chars(first, line.data() + line.size(), id);
  if (ec != std::errc() || line.rfind("{\"id\":", 0) != 0)
    throw Error(fmt::format("{}: not a frame's COCO file (sylva study): {}", file.string(), line.substr(0, 40)));
  return id;
}

}  // namespace

std::string frame_coco(const FrameAnnotationInput& in) {
  const Image& image = *in.image;
  std::string out = "{\"images\": [\n";
  out += fmt::format("{{\"id\": {}, \"file_name\": {}, \"width\": {}, \"height\": {}, \"sylva_frame\": \"{}\", {}}}\n",
                     in.frame_index + 1, json_string(in.image_file), image.width, image.height, in.frame_id,
                     one_line(view_json(in.file->scene, image.width, image.height)));
  out += "],\n\"annotations\": [\n";
  std::map<uint32_t, std::string> categories;
  bool first = true;
  for (size_t k = 0; k < in.targets.size(); ++k) {
    const TargetAnnotation& a = in.targets[k];
    categories[a.class_id] = a.label;
    if (a.visible_pixels == 0) continue;
    out += fmt::format("{}{}", first ? "" : ",\n", coco_annotation(in, a, k));
    first = false;
  }
  out += std::string(first ? "" : "\n") + "],\n\"categories\": [\n";
  first = true;
  for (const auto& [id, name] : categories) {
    out += fmt::format("{}{{\"id\": {}, \"name\": {}, \"supercategory\": \"target\"}}", first ? "" : ",\n", id,
                       json_string(name));
    first = false;
  }
  return out + std::string(first ? "" : "\n") + "]}\n";
}

std::string frame_yolo(const FrameAnnotationInput& in, const std::vector<std::string>& classes) {
  std::string out;
  const double w = in.image->width, h = in.image->height;
  for (const TargetAnnotation& a : in.targets) {
    if (a.visible_pixels == 0) continue;
    const auto row = std::find(classes.begin(), classes.end(), a.label);
    if (row == classes.end()) throw Error("YOLO: class '" + a.label + "' is not in the study's class list");
    const PixelBox& b = a.modal_box;
    out += fmt::format("{} {:.6f} {:.6f} {:.6f} {:.6f}\n", row - classes.begin(), (b.x0 + 0.5 * b.width()) / w,
                       (b.y0 + 0.5 * b.height()) / h, b.width() / w, b.height() / h);
  }
  return out;
}

std::string frame_voc(const FrameAnnotationInput& in) {
  const Image& image = *in.image;
  std::string out = "<annotation>\n";
  out += fmt::format("  <filename>{}</filename>\n", xml_text(in.image_file));
  out +=
      fmt::format("  <size><width>{}</width><height>{}</height><depth>3</depth></size>\n  <segmented>1</segmented>\n",
                  image.width, image.height);
  for (const TargetAnnotation& a : in.targets) {
    if (a.visible_pixels == 0) continue;
    const PixelBox& b = a.modal_box;
    out += fmt::format(
        "  <object>\n    <name>{}</name>\n    <pose>Unspecified</pose>\n    <truncated>{}</truncated>\n"
        "    <occluded>{}</occluded>\n    <difficult>0</difficult>\n"
        "    <bndbox><xmin>{}</xmin><ymin>{}</ymin><xmax>{}</xmax><ymax>{}</ymax></bndbox>\n  </object>\n",
        xml_text(a.label), a.truncated ? 1 : 0, a.visible_pixels < a.unoccluded_pixels ? 1 : 0, b.x0 + 1, b.y0 + 1,
        b.x1 + 1, b.y1 + 1);
  }
  return out + "</annotation>\n";
}

std::string study_coco(const std::vector<std::filesystem::path>& frame_files, const std::string& description) {
  std::string images, annotations;
  std::map<int64_t, std::string> categories;
  for (const std::filesystem::path& f : frame_files) {
    std::istringstream in(read_input_file(f, kMaxSceneFileBytes, "frame annotations"));
    std::string line;
    int part = -1;  // 0 images, 1 annotations, 2 categories
    while (std::getline(in, line)) {
      if (line == "{\"images\": [")
        part = 0;
      else if (line == "\"annotations\": [")
        part = 1;
      else if (line == "\"categories\": [")
        part = 2;
      else if (line == "]," || line == "]}")
        continue;
      else if (part < 0)
        throw Error(f.string() + ": not a frame's COCO file (sylva study)");
      else {
        if (!line.empty() && line.back() == ',') line.pop_back();
        if (part == 0) images += fmt::format("{}{}", images.empty() ? "\n    " : ",\n    ", line);
        if (part == 1) annotations += fmt::format("{}{}", annotations.empty() ? "\n    " : ",\n    ", line);
        if (part == 2) categories[category_id(line, f)] = line;
      }
    }
    if (part != 2) throw Error(f.string() + ": not a frame's COCO file (sylva study)");
  }
  std::string cats;
  for (const auto& [id, line] : categories) cats += fmt::format("{}{}", cats.empty() ? "\n    " : ",\n    ", line);
  return fmt::format(
      "{{\n  \"info\": {{\"description\": {}, \"version\": \"1\", \"contributor\": \"sylva study\"}},\n  \"licenses\": "
      "[],\n"
      "  \"images\": [{}\n  ],\n  \"annotations\": [{}\n  ],\n  \"categories\": [{}\n  ]\n}}\n",
      json_string(description), images, annotations, cats);
}

}  // namespace sylva
