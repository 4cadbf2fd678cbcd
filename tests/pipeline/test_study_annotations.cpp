// A study's annotations (scenes/annotations.h, pipeline/study_annotations.h): masks and boxes
// against the id AOVs, amodal boxes against a render without the occluder, the RLE round trip, and
// the COCO file checked against the schema with Python's standard json (tests/pipeline/check_coco.py).

#include "core/image.h"
#include "pipeline/study.h"
#include "scenes/annotations.h"
#include "tests/support/json_parse.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace sylva {
namespace {

// The vehicle behind a wall that hides its left part, seen from the south.
const std::string kAnnotatedScene = R"([render]
width = 48
height = 32
spp = 1
bands = ["rgb"]
max_depth = 2
[camera]
position = [0.0, -14.0, 2.0]
target = [0.0, 0.0, 1.0]
vfov = 40
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
[[meshes]]
name = "wall"
shape = "box"
size = [2.5, 0.2, 4.0]
translate = [-1.8, -5.0, 0.0]
material = "grey"
class = "wall"
[[targets]]
name = "tank"
file = "targets/vehicle.obj"
material = "camo"
label = "vehicle"
position = [0, 0, 0]
heading = 90
)";

std::string read_whole_file(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<uint8_t> decode_rle(const std::vector<uint64_t>& counts, int width, int height) {
  std::vector<uint8_t> mask(static_cast<size_t>(width) * static_cast<size_t>(height), 0);
  uint64_t k = 0;
  uint8_t value = 0;
  for (const uint64_t run : counts) {
    for (uint64_t i = 0; i < run; ++i, ++k) {
      const uint64_t x = k / static_cast<uint64_t>(height), y = k % static_cast<uint64_t>(height);
      mask[y * static_cast<uint64_t>(width) + x] = value;
    }
    value = 1 - value;
  }
  EXPECT_EQ(k, static_cast<uint64_t>(width) * static_cast<uint64_t>(height));
  return mask;
}

// The inclusive box of the pixels whose id.object is `object`.
PixelBox box_of(const Image& image, float object) {
  const int c = image.find_channel("id.object");
  PixelBox b;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      if (image.at(x, y, c) == object) {
        if (b.empty()) b = {x, y, x, y};
        b.x0 = std::min(b.x0, x);
        b.y0 = std::min(b.y0, y);
        b.x1 = std::max(b.x1, x);
        b.y1 = std::max(b.y1, y);
      }
  return b;
}

class StudyAnnotations : public test::TempDirTest {};

TEST_F(StudyAnnotations, RleRoundTrip) {
  const int w = 13, h = 7;
  std::vector<uint8_t> mask(static_cast<size_t>(w * h));
  for (size_t i = 0; i < mask.size(); ++i) mask[i] = static_cast<uint8_t>((i * 7919 + i / 5) % 3 == 0);
  EXPECT_EQ(decode_rle(rle_counts(mask, w, h), w, h), mask);
  const std::vector<uint8_t> ones(static_cast<size_t>(w * h), 1);
  EXPECT_EQ(rle_counts(ones, w, h), (std::vector<uint64_t>{0, static_cast<uint64_t>(w * h)}));  // starts with zeros
}

TEST_F(StudyAnnotations, MasksBoxesAndCocoAgreeWithTheIdAovs) {
  std::ofstream(dir_ / "scene.toml") << kAnnotatedScene;
  std::ofstream(dir_ / "study.toml") << "[study]\nscene = \"scene.toml\"\noutput = \"out\"\n[[factors]]\nname = "
                                        "\"elevation\"\nset = \"sun.elevation\"\nvalues = [30, 60]\n";
  RenderObserver observer;
  StudyRunOptions run;
  run.threads = 2;
  const StudyResult r = run_study(load_study(dir_ / "study.toml"), run, observer);
  ASSERT_EQ(r.rendered, 2u);
  const std::filesystem::path out = dir_ / "out";
  const std::string id = r.frames[0].id;
  const Image image = read_exr(out / "frames" / (id + ".exr"));
  const test::Json coco = test::JsonParser(read_whole_file(out / "frames" / (id + ".coco.json"))).parse();
  ASSERT_EQ(coco["annotations"].array.size(), 1u);
  const test::Json& a = coco["annotations"][0];
  const test::Json sidecar = test::JsonParser(read_whole_file(out / "frames" / (id + ".json"))).parse();
  const auto object = static_cast<float>(sidecar["targets"][0]["object"].number);
  // The modal box and mask are the id AOV's.
  const PixelBox modal = box_of(image, object);
  ASSERT_FALSE(modal.empty());
  EXPECT_EQ(a["bbox"][0].number, modal.x0);
  EXPECT_EQ(a["bbox"][1].number, modal.y0);
  EXPECT_EQ(a["bbox"][2].number, modal.width());
  EXPECT_EQ(a["bbox"][3].number, modal.height());
  std::vector<uint64_t> counts;
  for (const test::Json& c : a["segmentation"]["counts"].array) counts.push_back(static_cast<uint64_t>(c.number));
  const std::vector<uint8_t> mask = decode_rle(counts, image.width, image.height);
  const int c = image.find_channel("id.object");
  uint64_t area = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const bool on = image.at(x, y, c) == object;
      EXPECT_EQ(mask[static_cast<size_t>(y * image.width + x)], on ? 1 : 0) << x << ", " << y;
      area += on;
    }
  EXPECT_EQ(a["area"].number, static_cast<double>(area));
  EXPECT_EQ(a["category_id"].number, coco["categories"][0]["id"].number);
  EXPECT_EQ(coco["categories"][0]["name"].string, "vehicle");

  // The amodal box is the box of a render without the wall; the wall hides part of the target.
  RenderCallOptions alone;
  alone.request.source = SceneSource::from_file((dir_ / "scene.toml").string());
  alone.request.overrides = r.frames[0].overrides;
  alone.request.overrides.push_back("meshes.wall.translate=[0, 500, 0]");
  alone.exr = dir_ / "alone.exr";
  ASSERT_EQ(render_scene(alone, observer).status, RenderStatus::finished);
  const PixelBox amodal = box_of(read_exr(dir_ / "alone.exr"), object);
  EXPECT_EQ(a["amodal_bbox"][0].number, amodal.x0);
  EXPECT_EQ(a["amodal_bbox"][1].number, amodal.y0);
  EXPECT_EQ(a["amodal_bbox"][2].number, amodal.width());
  EXPECT_EQ(a["amodal_bbox"][3].number, amodal.height());
  EXPECT_LT(modal.width(), amodal.width()) << "the wall hides the left of the vehicle";
  EXPECT_GT(a["visible_fraction"].number, 0.1);
  EXPECT_LT(a["visible_fraction"].number, 0.95);
  EXPECT_NEAR(a["characteristic_dimension_px"].number, std::sqrt(a["unoccluded_pixels"].number), 1e-9);

  // YOLO and VOC.
  std::ifstream yolo(out / "frames" / (id + ".txt"));
  int cls = -1;
  double cx = 0, cy = 0, bw = 0, bh = 0;
  yolo >> cls >> cx >> cy >> bw >> bh;
  EXPECT_EQ(cls, 0);
  EXPECT_NEAR(bw, modal.width() / 48.0, 1e-6);
  EXPECT_NEAR(cx, (modal.x0 + 0.5 * modal.width()) / 48.0, 1e-6);
  const std::string voc = read_whole_file(out / "frames" / (id + ".xml"));
  EXPECT_NE(voc.find("<xmin>" + std::to_string(modal.x0 + 1) + "</xmin>"), std::string::npos);
  EXPECT_NE(voc.find("<occluded>1</occluded>"), std::string::npos);

  // The study's COCO file, checked with Python's json against the schema (RLE decoded there too).
  ASSERT_TRUE(std::filesystem::exists(out / "coco.json"));
  const std::string command = "python3 " SYLVA_SOURCE_DIR "/tests/pipeline/check_coco.py '" +
                              (out / "coco.json").string() + "' > '" + (dir_ / "check.txt").string() + "' 2>&1";
  EXPECT_EQ(std::system(command.c_str()), 0) << read_whole_file(dir_ / "check.txt");
  const test::Json study = test::JsonParser(read_whole_file(out / "coco.json")).parse();
  EXPECT_EQ(study["images"].array.size(), 2u);
  EXPECT_EQ(study["annotations"].array.size(), 2u);
}

TEST_F(StudyAnnotations, AmodalBoxesAreClippedToTheImage) {
  // The camera turned right so the vehicle leaves the image on the left: its boxes are clipped to
  // the image, and it is truncated in COCO and VOC.
  std::ofstream(dir_ / "scene.toml") << kAnnotatedScene;
  std::ofstream(dir_ / "study.toml")
      << "[study]\nscene = \"scene.toml\"\noutput = \"out\"\n"
         "set = [\"camera.target=[7.5, 0, 1]\", \"meshes.wall.translate=[0, 500, 0]\"]\n";
  RenderObserver observer;
  StudyRunOptions run;
  run.threads = 2;
  const StudyResult r = run_study(load_study(dir_ / "study.toml"), run, observer);
  ASSERT_EQ(r.rendered, 1u);
  const std::filesystem::path frames = dir_ / "out" / "frames";
  const std::string id = r.frames[0].id;
  const Image image = read_exr(frames / (id + ".exr"));
  const test::Json coco = test::JsonParser(read_whole_file(frames / (id + ".coco.json"))).parse();
  ASSERT_EQ(coco["annotations"].array.size(), 1u);
  const test::Json& a = coco["annotations"][0];
  EXPECT_EQ(a["amodal_bbox"][0].number, 0.0) << "the vehicle reaches the left border";
  EXPECT_LE(a["amodal_bbox"][0].number + a["amodal_bbox"][2].number, image.width);
  EXPECT_EQ(a["truncated"].number, 1.0);
  // Nothing hides it: the modal and amodal boxes agree, visible fraction 1.
  for (size_t k = 0; k < 4; ++k) EXPECT_EQ(a["bbox"][k].number, a["amodal_bbox"][k].number);
  EXPECT_EQ(a["visible_fraction"].number, 1.0);
  EXPECT_NE(read_whole_file(frames / (id + ".xml")).find("<truncated>1</truncated>"), std::string::npos);
  const std::string command = "python3 " SYLVA_SOURCE_DIR "/tests/pipeline/check_coco.py '" +
                              (dir_ / "out" / "coco.json").string() + "' > '" + (dir_ / "check.txt").string() +
                              "' 2>&1";
  EXPECT_EQ(std::system(command.c_str()), 0) << read_whole_file(dir_ / "check.txt");
}

}  // namespace
}  // namespace sylva
