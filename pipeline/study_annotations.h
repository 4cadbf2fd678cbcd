#pragma once
// The annotation files of a study's frames (docs/studies.md, "Annotations"), from the frame's scene
// and image (scenes/annotations.h): COCO (per frame, and one file for the study assembled from the
// frames'), YOLO and Pascal VOC.

#include "scenes/annotations.h"
#include "scenes/scene_file.h"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace sylva {

struct FrameAnnotationInput {
  size_t frame_index = 0;
  std::string frame_id;
  std::string image_file;  // as COCO's file_name and VOC's filename, relative to the output folder
  const SceneFile* file = nullptr;
  const Image* image = nullptr;
  std::vector<TargetAnnotation> targets;
};

// A frame's COCO file: one image (with the camera and sun), an annotation per visible target
// (modal bbox, amodal bbox, RLE mask, area, iscrowd 0, visible fraction, critical dimension) and
// the categories of its targets. One item per line, so study_coco() can assemble frames' files.
std::string frame_coco(const FrameAnnotationInput& in);

// YOLO: one line per visible target, "class cx cy w h" (the modal box, normalised to the image);
// the class is its label's row in `classes`.
std::string frame_yolo(const FrameAnnotationInput& in, const std::vector<std::string>& classes);

// Pascal VOC XML: the image size and one <object> per visible target (1-based inclusive box,
// truncated when the target's amodal box touches the image border, occluded when part is hidden).
std::string frame_voc(const FrameAnnotationInput& in);

// The study's COCO file: the images and annotations of the frames' files in order, and the union
// of their categories by id. Throws Error naming a file that is not a frame's COCO file.
std::string study_coco(const std::vector<std::filesystem::path>& frame_files, const std::string& description);

}  // namespace sylva
