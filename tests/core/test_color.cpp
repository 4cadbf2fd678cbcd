// The shipped OCIO config and PNG previews (core/color.h, write_png_preview).

#include "core/color.h"
#include "core/data_path.h"
#include "core/error.h"
#include "core/image.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <unistd.h>
#include <cmath>
#include <filesystem>
#include <fstream>

namespace sylva {
namespace {

namespace fs = std::filesystem;

// sRGB inverse EOTF (IEC 61966-2-1), the reference the Standard view must match.
double srgb_encode(double v) { return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055; }

std::vector<uint8_t> read_png(const fs::path& path, int& width, int& height) {
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) return {};
  width = in->spec().width;
  height = in->spec().height;
  EXPECT_EQ(in->spec().nchannels, 3);
  std::vector<uint8_t> bytes(static_cast<size_t>(width * height * 3));
  EXPECT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, bytes.data()));
  return bytes;
}

TEST(Color, ShippedConfigLoadsWithItsViews) {
  EXPECT_NO_THROW(validate_ocio_config());
  const std::vector<std::string> views = ocio_views();
  EXPECT_EQ(views, (std::vector<std::string>{"Standard", "ACES", "Raw"}));
}

TEST(Color, StandardViewIsTheSrgbEncoding) {
  std::vector<float> rgb{0.18f, 0.18f, 0.18f, 0.0f, 0.5f, 1.0f, 0.001f, 0.02f, 0.7f};
  const std::vector<float> in = rgb;
  apply_display_transform(rgb.data(), 3, "Standard");
  for (size_t i = 0; i < rgb.size(); ++i) EXPECT_NEAR(rgb[i], srgb_encode(in[i]), 2e-4) << i;
  EXPECT_EQ(std::lround(rgb[0] * 255.0f), 118);  // mid grey
}

TEST(Color, AcesViewToneMapsAndRawPassesThrough) {
  std::vector<float> aces{0.18f, 0.18f, 0.18f, 1.0f, 1.0f, 1.0f, 16.0f, 16.0f, 16.0f};
  apply_display_transform(aces.data(), 3, "ACES");
  EXPECT_GT(aces[0], 0.25f);    // mid grey stays mid
  EXPECT_LT(aces[0], 0.45f);    // ... but darker than the colorimetric encoding (the filmic toe)
  EXPECT_LT(aces[3], 0.95f);    // diffuse white is below display white
  EXPECT_GT(aces[6], aces[3]);  // highlights roll off monotonically ...
  EXPECT_LE(aces[6], 1.0001f);  // ... and never exceed display white
  std::vector<float> raw{0.18f, 4.0f, -1.0f};
  apply_display_transform(raw.data(), 1, "Raw");
  EXPECT_EQ(raw, (std::vector<float>{0.18f, 4.0f, -1.0f}));
}

TEST(Color, UnknownViewNamesTheAvailableOnes) {
  float rgb[3] = {0.1f, 0.1f, 0.1f};
  try {
    apply_display_transform(rgb, 1, "Filmic Log");
    FAIL() << "expected sylva::Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("Standard, ACES, Raw"), std::string::npos) << e.what();
  }
}

TEST(Color, BrokenConfigIsReportedWithItsPath) {
  const fs::path path = fs::temp_directory_path() / ("sylva_bad_ocio_" + std::to_string(::getpid()) + ".ocio");
  std::ofstream(path) << "ocio_profile_version: 2.1\nroles: {scene_linear: nowhere}\ndisplays: {}\n";
  try {
    validate_ocio_config(path);
    FAIL() << "expected sylva::Error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind(path.string() + ": ", 0), 0u) << e.what();
  }
  fs::remove(path);
}

TEST(Color, PngPreviewOfMidGreyAndAGreyBand) {
  const fs::path dir = fs::temp_directory_path() / ("sylva_test_png_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  Image image = make_image(4, 2, {"R", "G", "B", "nir.Y"});
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 4; ++x) {
      image.at(x, y, 0) = 0.18f;
      image.at(x, y, 1) = 0.18f;
      image.at(x, y, 2) = 0.18f;
      image.at(x, y, 3) = x == 0 ? 0.09f : 1.0f;
    }
  image.at(3, 1, 0) = std::nanf("");  // NaN never reaches the PNG as garbage
  write_png_preview(dir / "rgb.png", image, {});
  int w = 0, h = 0;
  std::vector<uint8_t> px = read_png(dir / "rgb.png", w, h);
  ASSERT_EQ(w, 4);
  ASSERT_EQ(h, 2);
  EXPECT_EQ(px[0], 118);
  EXPECT_EQ(px[1], 118);
  EXPECT_EQ(px[2], 118);
  EXPECT_EQ(px[(1 * 4 + 3) * 3 + 0], 0);

  PreviewOptions nir;
  nir.channels = {"nir.Y", "nir.Y", "nir.Y"};
  nir.exposure_ev = 1.0f;  // 0.09 · 2 = 0.18
  write_png_preview(dir / "nir.png", image, nir);
  px = read_png(dir / "nir.png", w, h);
  EXPECT_EQ(px[0], 118);
  EXPECT_EQ(px[1], 118);
  EXPECT_EQ(px[3], 255);  // 2.0 clips to white

  PreviewOptions missing;
  missing.channels = {"albedo.R", "albedo.G", "albedo.B"};
  EXPECT_THROW(write_png_preview(dir / "none.png", image, missing), Error);
  EXPECT_FALSE(fs::exists(dir / "none.png"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace sylva
