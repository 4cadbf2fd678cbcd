// EXR round trip, atomic writes, read errors and PNG previews (core/image.h).

#include "core/error.h"
#include "core/image.h"
#include "tests/support/atomic_temporaries.h"
#include "tests/support/temp_dir.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <unistd.h>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace sylva {
namespace {

namespace fs = std::filesystem;

using ImageFiles = test::TempDirTest;

Image sample_image() {
  Image image = make_image(5, 3, {"R", "G", "B", "nir.Y", "Z"});
  image.add_channel("id.instance", PixelType::UInt);
  image.add_channel("N.X", PixelType::Half);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      image.at(x, y, 0) = 0.1f * static_cast<float>(x) + 1e-7f;
      image.at(x, y, 1) = 1000.0f + 0.001f * static_cast<float>(y);
      image.at(x, y, 2) = -0.25f;
      image.at(x, y, 3) = static_cast<float>(x * y) / 7.0f;
      image.at(x, y, 4) = 3.0e4f;
      image.at(x, y, 5) = static_cast<float>((1 << 24) - 1 - x - 10 * y);  // large ids stay exact
      image.at(x, y, 6) = 0.5f + 0.25f * static_cast<float>(x);            // exact in half
    }
  image.attributes = {{"sylva:spp", "256"}, {"sylva:scene", "default, seed=7"}};
  return image;
}

TEST(Image, ChannelsAndAttributes) {
  Image image = make_image(2, 2, {"R", "G"});
  image.at(1, 1, 0) = 3.0f;
  image.at(1, 0, 1) = 4.0f;
  image.add_channel("Z", PixelType::Float);
  ASSERT_EQ(image.channel_count(), 3);
  EXPECT_EQ(image.find_channel("Z"), 2);
  EXPECT_EQ(image.find_channel("B"), -1);
  EXPECT_EQ(image.at(1, 1, 0), 3.0f);
  EXPECT_EQ(image.at(1, 0, 1), 4.0f);
  EXPECT_EQ(image.at(1, 1, 2), 0.0f);
  EXPECT_EQ(image.pixels.size(), 12u);
  EXPECT_EQ(image.attribute("sylva:spp"), "");
  image.set_attribute("sylva:spp", "16");
  image.set_attribute("sylva:spp", "32");
  EXPECT_EQ(image.attribute("sylva:spp"), "32");
  EXPECT_EQ(image.attributes.size(), 1u);
}

TEST_F(ImageFiles, ExrRoundTripKeepsNamesTypesValuesAndHeader) {
  const Image image = sample_image();
  const fs::path path = dir_ / "round.exr";
  write_exr(path, image);
  const Image back = read_exr(path);
  ASSERT_EQ(back.width, image.width);
  ASSERT_EQ(back.height, image.height);
  ASSERT_EQ(back.channel_count(), image.channel_count());
  for (int c = 0; c < image.channel_count(); ++c) {
    const int bc = back.find_channel(image.channels[static_cast<size_t>(c)]);
    ASSERT_GE(bc, 0) << image.channels[static_cast<size_t>(c)];
    EXPECT_EQ(back.types[static_cast<size_t>(bc)], image.types[static_cast<size_t>(c)])
        << image.channels[static_cast<size_t>(c)];
    for (int y = 0; y < image.height; ++y)
      for (int x = 0; x < image.width; ++x)
        EXPECT_EQ(back.at(x, y, bc), image.at(x, y, c))
            << image.channels[static_cast<size_t>(c)] << " " << x << "," << y;
  }
  EXPECT_EQ(back.attribute("sylva:spp"), "256");
  EXPECT_EQ(back.attribute("sylva:scene"), "default, seed=7");
  EXPECT_EQ(back.attribute("compression"), "");  // the header's own fields are not image attributes

  // The file itself: ZIP, UINT ids, Rec.709 chromaticities.
  auto in = OIIO::ImageInput::open(path.string());
  ASSERT_TRUE(in);
  const OIIO::ImageSpec& spec = in->spec();
  EXPECT_EQ(spec.get_string_attribute("compression"), "zip");
  EXPECT_EQ(spec.channelformat(spec.channelindex("id.instance")), OIIO::TypeDesc::UINT32);
  EXPECT_EQ(spec.channelformat(spec.channelindex("N.X")), OIIO::TypeDesc::HALF);
  EXPECT_EQ(spec.channelformat(spec.channelindex("R")), OIIO::TypeDesc::FLOAT);
  const OIIO::ParamValue* chroma = spec.find_attribute("chromaticities");
  ASSERT_NE(chroma, nullptr);
  ASSERT_EQ(chroma->type(), OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8));
  const float* xy = static_cast<const float*>(chroma->data());
  for (size_t i = 0; i < 8; ++i) EXPECT_FLOAT_EQ(xy[i], rec709_chromaticities[i]) << i;
}

TEST_F(ImageFiles, SameImageGivesIdenticalBytes) {
  const Image image = sample_image();
  write_exr(dir_ / "a.exr", image);
  write_exr(dir_ / "b.exr", image);  // no capture date is stamped (to the second)
  auto bytes = [](const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  const std::string a = bytes(dir_ / "a.exr");
  EXPECT_FALSE(a.empty());
  EXPECT_EQ(a, bytes(dir_ / "b.exr"));
  EXPECT_EQ(read_exr(dir_ / "a.exr").attribute("DateTime"), "");
  Image stamped = image;
  stamped.set_attribute("DateTime", "2026:01:02 03:04:05");
  write_exr(dir_ / "c.exr", stamped);
  EXPECT_EQ(read_exr(dir_ / "c.exr").attribute("DateTime"), "2026:01:02 03:04:05");
}

TEST_F(ImageFiles, ChannelsAreReadByLayerWithColourFirst) {
  // OpenEXR stores channels sorted by name; they come back by layer (unlayered first), R, G, B, A
  // first within a layer, then by name.
  Image image = make_image(2, 1, {"var.R", "Z", "B", "albedo.G", "A", "R", "var.B", "G", "N.X", "albedo.R"});
  for (int c = 0; c < image.channel_count(); ++c) image.at(1, 0, c) = static_cast<float>(c);
  write_exr(dir_ / "order.exr", image);
  const Image back = read_exr(dir_ / "order.exr");
  const std::vector<std::string> expected{"R", "G", "B", "A", "Z", "N.X", "albedo.R", "albedo.G", "var.R", "var.B"};
  EXPECT_EQ(back.channels, expected);
  for (int c = 0; c < back.channel_count(); ++c)
    EXPECT_EQ(back.at(1, 0, c), static_cast<float>(image.find_channel(back.channels[static_cast<size_t>(c)])));
}

TEST_F(ImageFiles, PngPreviewIsTaggedSrgb) {
  write_png_rgb8(dir_ / "s.png", 1, 1, {10, 20, 30});
  std::ifstream in(dir_ / "s.png", std::ios::binary);
  const std::string bytes{std::istreambuf_iterator<char>(in), {}};
  EXPECT_EQ(bytes.compare(0, 8, "\x89PNG\r\n\x1a\n"), 0);
  EXPECT_NE(bytes.find("sRGB"), std::string::npos);
  const Image image = read_exr(dir_ / "s.png");
  EXPECT_FLOAT_EQ(image.at(0, 0, 2), 30.0f / 255.0f);
}

TEST_F(ImageFiles, PngSamplesAreReadByLibpngAsOpenImageIoWroteThem) {
  // 16-bit grey (a terrain raster) keeps its integer values; 8-bit RGBA reads as normalised colour.
  const std::vector<uint16_t> grey{0, 1, 256, 4097, 65534, 65535};
  {
    auto out = OIIO::ImageOutput::create("png");
    ASSERT_TRUE(out && out->open((dir_ / "grey.png").string(), OIIO::ImageSpec(3, 2, 1, OIIO::TypeDesc::UINT16)));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT16, grey.data()));
    ASSERT_TRUE(out->close());
  }
  const Raster r = read_raster(dir_ / "grey.png");
  ASSERT_EQ(r.type, RasterType::UInt16);
  ASSERT_EQ(r.values.size(), grey.size());
  for (size_t i = 0; i < grey.size(); ++i) EXPECT_EQ(r.values[i], static_cast<float>(grey[i])) << i;

  const std::vector<uint8_t> rgba{0, 51, 102, 255, 255, 204, 153, 0};
  {
    auto out = OIIO::ImageOutput::create("png");
    ASSERT_TRUE(out && out->open((dir_ / "rgba.png").string(), OIIO::ImageSpec(2, 1, 4, OIIO::TypeDesc::UINT8)));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, rgba.data()));
    ASSERT_TRUE(out->close());
  }
  const Image image = read_exr(dir_ / "rgba.png");
  ASSERT_EQ(image.channels, (std::vector<std::string>{"R", "G", "B", "A"}));
  for (int x = 0; x < 2; ++x)
    for (int c = 0; c < 4; ++c)
      EXPECT_FLOAT_EQ(image.at(x, 0, c), static_cast<float>(rgba[static_cast<size_t>(4 * x + c)]) / 255.0f);
}

TEST_F(ImageFiles, CroppedDataWindowIsPlacedInTheDisplayWindow) {
  // As other renderers write an auto-cropped EXR: 2×1 data window at (3, 2) of a 6×4 display.
  OIIO::ImageSpec spec(2, 1, 1, OIIO::TypeDesc::FLOAT);
  spec.x = 3;
  spec.y = 2;
  spec.full_x = 0;
  spec.full_y = 0;
  spec.full_width = 6;
  spec.full_height = 4;
  spec.channelnames = {"Y"};
  const float data[2] = {5.0f, 7.0f};
  const fs::path path = dir_ / "crop.exr";
  auto out = OIIO::ImageOutput::create("openexr");
  ASSERT_TRUE(out && out->open(path.string(), spec));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, data));
  ASSERT_TRUE(out->close());
  const Image image = read_exr(path);
  ASSERT_EQ(image.width, 6);
  ASSERT_EQ(image.height, 4);
  float sum = 0.0f;
  for (float v : image.pixels) sum += v;
  EXPECT_EQ(sum, 12.0f);
  EXPECT_EQ(image.at(3, 2, 0), 5.0f);
  EXPECT_EQ(image.at(4, 2, 0), 7.0f);
}

TEST_F(ImageFiles, EightBitFilesAreNormalisedColour) {
  write_png_rgb8(dir_ / "c.png", 2, 1, {0, 51, 255, 255, 0, 0});
  const Image image = read_exr(dir_ / "c.png");
  ASSERT_EQ(image.channel_count(), 3);
  EXPECT_EQ(image.types[0], PixelType::Float);
  EXPECT_FLOAT_EQ(image.at(0, 0, 1), 0.2f);
  EXPECT_FLOAT_EQ(image.at(0, 0, 2), 1.0f);
}

TEST_F(ImageFiles, NoChromaticitiesWithoutRgb) {
  Image image = make_image(2, 2, {"nir.Y"});
  write_exr(dir_ / "nir.exr", image);
  auto in = OIIO::ImageInput::open((dir_ / "nir.exr").string());
  ASSERT_TRUE(in);
  EXPECT_EQ(in->spec().find_attribute("chromaticities"), nullptr);
}

// Another tool's file may have a text attribute named `chromaticities`; an image read from it (and
// written again by `sylva compare --report`) keeps it, rather than failing on OpenEXR's type clash.
TEST_F(ImageFiles, TextChromaticitiesAttributeIsKept) {
  Image image = make_image(2, 2, {"R", "G", "B"});
  image.set_attribute("chromaticities", "rec709");
  write_exr(dir_ / "text.exr", image);
  EXPECT_EQ(read_exr(dir_ / "text.exr").attribute("chromaticities"), "rec709");
}

TEST_F(ImageFiles, OverwriteReplacesAndLeavesNoTemporary) {
  Image image = make_image(3, 2, {"Y"});
  const fs::path path = dir_ / "a.exr";
  write_exr(path, image);
  image.at(2, 1, 0) = 9.0f;
  write_exr(path, image);
  EXPECT_EQ(read_exr(path).at(2, 1, 0), 9.0f);
  int entries = 0;
  for (const auto& e : fs::directory_iterator(dir_)) {
    ++entries;
    EXPECT_EQ(e.path().filename(), "a.exr");
  }
  EXPECT_EQ(entries, 1);
}

TEST_F(ImageFiles, FailedWriteThrowsAndLeavesNoPartialFile) {
  const Image image = sample_image();
  // A directory that cannot be written (skip the check when running as root, who bypasses modes).
  const fs::path locked = dir_ / "locked";
  fs::create_directories(locked);
  fs::permissions(locked, fs::perms::owner_read | fs::perms::owner_exec);
  if (::geteuid() != 0) {
    EXPECT_THROW(write_exr(locked / "out.exr", image), Error);
    EXPECT_TRUE(fs::is_empty(locked));
  }
  fs::permissions(locked, fs::perms::owner_all);
  // procfs refuses new files even to root.
  EXPECT_THROW(write_exr("/proc/sylva_test_unwritable.exr", image), Error);
  EXPECT_FALSE(fs::exists("/proc/sylva_test_unwritable.exr"));

  // A missing directory fails for everyone, root included; the message names the path.
  const fs::path missing = dir_ / "no" / "such" / "dir" / "out.exr";
  try {
    write_exr(missing, image);
    FAIL() << "expected sylva::Error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(missing.string()), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(missing));

  // The target is a directory: the temporary is written, the rename fails, the temporary goes away.
  const fs::path target = dir_ / "is_a_dir.exr";
  fs::create_directories(target / "child");
  EXPECT_THROW(write_exr(target, image), Error);
  EXPECT_TRUE(fs::is_directory(target));
  EXPECT_TRUE(test::atomic_temporaries_in(dir_).empty());

  // An inconsistent image is refused before anything is written.
  Image broken = make_image(2, 2, {"R"});
  broken.pixels.pop_back();
  EXPECT_THROW(write_exr(dir_ / "broken.exr", broken), Error);
  EXPECT_FALSE(fs::exists(dir_ / "broken.exr"));
}

TEST_F(ImageFiles, ReadErrorsAreClear) {
  auto message = [](const fs::path& p) {
    try {
      read_exr(p);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const fs::path missing = dir_ / "missing.exr";
  const std::string m1 = message(missing);
  EXPECT_EQ(m1.rfind(missing.string() + ": ", 0), 0u) << m1;
  EXPECT_NE(m1.find("no such file"), std::string::npos) << m1;

  const fs::path garbage = dir_ / "garbage.exr";
  std::ofstream(garbage) << "this is not an image";
  const std::string m2 = message(garbage);
  EXPECT_EQ(m2.rfind(garbage.string() + ": ", 0), 0u) << m2;

  // A truncated EXR: valid header, missing pixel data.
  Image image = make_image(64, 64, {"R", "G", "B"});
  for (size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] = static_cast<float>(i % 97) * 0.37f;
  const fs::path full = dir_ / "full.exr";
  write_exr(full, image);
  const fs::path cut = dir_ / "cut.exr";
  fs::copy_file(full, cut);
  fs::resize_file(cut, fs::file_size(full) / 2);
  const std::string m3 = message(cut);
  EXPECT_EQ(m3.rfind(cut.string() + ": ", 0), 0u) << m3;

  // A PNG cut inside its pixel data (libpng's error): one line naming the file.
  std::vector<uint8_t> rgb(64 * 64 * 3);
  for (size_t i = 0; i < rgb.size(); ++i) rgb[i] = static_cast<uint8_t>((i * 7919) % 251);
  const fs::path png = dir_ / "full.png";
  write_png_rgb8(png, 64, 64, rgb);
  const fs::path cut_png = dir_ / "cut.png";
  fs::copy_file(png, cut_png);
  fs::resize_file(cut_png, fs::file_size(png) / 2);
  const std::string m4 = message(cut_png);
  EXPECT_EQ(m4.rfind(cut_png.string() + ": cannot read pixels: ", 0), 0u) << m4;
  EXPECT_NE(m4.find("truncated"), std::string::npos) << m4;
  for (const std::string& m : {m1, m2, m3, m4}) EXPECT_EQ(m.find('\n'), std::string::npos) << m;
}

// The bytes of an EXR with one header value replaced: `field` is an attribute name, the 4 bytes at
// `offset` into its value become `value`.
std::string patched_exr(const fs::path& file, const std::string& field, size_t offset, int32_t value) {
  std::ifstream in(file, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const size_t name = bytes.find(field + '\0');
  const size_t type_end = bytes.find('\0', name + field.size() + 1);
  EXPECT_NE(name, std::string::npos) << field;
  std::memcpy(bytes.data() + type_end + 1 + offset, &value, sizeof value);
  return bytes;
}

// Headers claiming windows, channels or attribute sizes beyond the limits are refused before
// anything is allocated from them (fuzzing found both: tests/data/fuzz/exr/).
TEST_F(ImageFiles, HostileHeadersAreRefusedBeforeAllocating) {
  Image image = make_image(8, 6, {"R", "G", "B"});
  const fs::path good = dir_ / "good.exr";
  write_exr(good, image);
  const auto refusal = [&](const std::string& bytes) {
    const fs::path file = dir_ / "hostile.exr";
    std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
    try {
      read_exr(file);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  // The value of an attribute starts 4 bytes (its size) after the type name.
  const std::string huge_display = refusal(patched_exr(good, "displayWindow", 4 + 8, 779247990));
  EXPECT_NE(huge_display.find("limit of 0 to 65536 pixels per side"), std::string::npos) << huge_display;
  // A data window within the side limit but far more pixels than a small file can hold.
  std::string wide = patched_exr(good, "dataWindow", 4 + 8, 60000);
  const fs::path wide_file = dir_ / "wide.exr";
  std::ofstream(wide_file, std::ios::binary) << wide;
  const std::string huge_data = refusal(patched_exr(wide_file, "dataWindow", 4 + 12, 60000));
  EXPECT_NE(huge_data.find("more than a file of"), std::string::npos) << huge_data;
  // An attribute claiming more bytes than the file has.
  const std::string huge_attribute = refusal(patched_exr(good, "pixelAspectRatio", 0, 1970601985));
  EXPECT_NE(huge_attribute.find("claims 1970601985 bytes"), std::string::npos) << huge_attribute;
  // A name holding a line break (fuzzing made such names) is quoted on one line.
  std::string broken_name = patched_exr(good, "pixelAspectRatio", 0, 1970601985);
  broken_name[broken_name.find("pixelAspectRatio")] = '\n';
  const std::string quoted = refusal(broken_name);
  EXPECT_NE(quoted.find("'\\x0aixelAspectRatio' claims"), std::string::npos) << quoted;
  EXPECT_EQ(quoted.find('\n'), std::string::npos) << quoted;
  // The unpatched file still reads.
  EXPECT_EQ(read_exr(good).width, 8);
}

// A header must have every attribute the EXR format requires, with its type: OpenEXR spent 3 s and
// 2 GB on a header without a data window (fuzzing, tests/data/fuzz/exr/), so such headers are
// refused before OpenEXR opens the file. A file that ends inside its header is refused likewise.
TEST_F(ImageFiles, HeadersWithoutARequiredAttributeAreRefused) {
  Image image = make_image(8, 6, {"R", "G", "B"});
  const fs::path good = dir_ / "good.exr";
  write_exr(good, image);
  std::ifstream in(good, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto refusal = [&](const std::string& hostile) {
    const fs::path file = dir_ / "hostile.exr";
    std::ofstream(file, std::ios::binary | std::ios::trunc) << hostile;
    try {
      read_exr(file);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  for (const std::string name : {"channels", "compression", "dataWindow", "displayWindow", "lineOrder",
                                 "pixelAspectRatio", "screenWindowCenter", "screenWindowWidth"}) {
    // Renaming the attribute (same length, so the layout is unchanged) removes it.
    std::string renamed = bytes;
    const size_t at = renamed.find(name + '\0');
    ASSERT_NE(at, std::string::npos) << name;
    renamed[at] = 'X';
    const std::string message = refusal(renamed);
    EXPECT_NE(message.find("lacks the required attribute(s) '" + name + "'"), std::string::npos) << message;
    // The attribute under its name but with another type.
    std::string retyped = bytes;
    const size_t type = at + name.size() + 1;
    retyped[type] = retyped[type] == 'X' ? 'Y' : 'X';
    const std::string message2 = refusal(retyped);
    EXPECT_NE(message2.find("header attribute '" + name + "' is a "), std::string::npos) << message2;
  }
  // Cut inside the header (after the channel list).
  const std::string cut = refusal(bytes.substr(0, bytes.find("compression")));
  EXPECT_NE(cut.find("ends inside its EXR header"), std::string::npos) << cut;
  // The input fuzzing found: capDate and channels, then the end of the header.
  const fs::path kept = fs::path(SYLVA_SOURCE_DIR) / "tests/data/fuzz/exr/header_without_data_window.exr";
  std::ifstream kept_in(kept, std::ios::binary);
  const std::string kept_bytes(std::istreambuf_iterator<char>(kept_in), {});
  const std::string m = refusal(kept_bytes);
  EXPECT_NE(m.find("lacks the required attribute(s) 'compression', 'dataWindow', 'displayWindow'"), std::string::npos)
      << m;
  // A header of any length is walked to its end: that input behind a 70 000-byte text attribute
  // (OpenEXR spent 1.9 GB on it when the check read only the first 64 KiB); a complete header of
  // that length still reads.
  std::string pad = "pad";
  pad += '\0';
  pad += "string";
  pad += '\0';
  const int32_t pad_size = 70000;
  pad.append(reinterpret_cast<const char*>(&pad_size), sizeof pad_size);
  pad.append(static_cast<size_t>(pad_size), 'x');
  const std::string padded = refusal(kept_bytes.substr(0, 8) + pad + kept_bytes.substr(8));
  EXPECT_NE(padded.find("lacks the required attribute(s) 'compression', 'dataWindow', 'displayWindow'"),
            std::string::npos)
      << padded;
  Image long_header = image;
  long_header.set_attribute("pad", std::string(70000, 'x'));
  write_exr(dir_ / "long_header.exr", long_header);
  EXPECT_EQ(read_exr(dir_ / "long_header.exr").attribute("pad"), std::string(70000, 'x'));
  // A name longer than OpenEXR's 255 bytes.
  std::string long_name = bytes;
  long_name.insert(8, std::string(300, 'n'));
  const std::string named = refusal(long_name);
  EXPECT_NE(named.find("is longer than 255 bytes"), std::string::npos) << named;
  EXPECT_EQ(read_exr(good).width, 8);
}

}  // namespace
}  // namespace sylva
