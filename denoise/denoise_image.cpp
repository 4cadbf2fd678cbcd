#include "denoise/denoise_image.h"

#include "core/error.h"

#include <fmt/core.h>

#include <array>

namespace sylva {

namespace {

int required(const Image& image, const std::string& name) {
  const int c = image.find_channel(name);
  if (c < 0)
    throw Error(
        fmt::format("the image has no {} channel: the denoiser needs the features of a render made with "
                    "--features or --denoise (docs/denoise.md)",
                    name));
  return c;
}

}  // namespace

std::vector<std::string> denoisable_channels(const Image& image) {
  std::vector<std::string> out;
  for (const std::string& name : image.channels) {
    if (name.rfind("even.", 0) != 0) continue;
    const std::string c = name.substr(5);
    if (image.find_channel(c) >= 0 && image.find_channel("odd." + c) >= 0 && image.find_channel("var." + c) >= 0)
      out.push_back(c);
  }
  return out;
}

DenoiseBuffers denoise_buffers(const Image& image) {
  if (!image.attribute("sylva:denoised").empty())
    throw Error("the image is already denoised (" + image.attribute("sylva:denoised") + ")");
  const std::vector<std::string> channels = denoisable_channels(image);
  if (channels.empty())
    throw Error(
        "the image has no half-buffers (even.<C>, odd.<C>): the denoiser needs the features of a render made "
        "with --features or --denoise (docs/denoise.md)");
  const int nc = static_cast<int>(channels.size());
  std::vector<int> beauty, even, odd, var, albedo;
  for (const std::string& c : channels) {
    beauty.push_back(image.find_channel(c));
    even.push_back(image.find_channel("even." + c));
    odd.push_back(image.find_channel("odd." + c));
    var.push_back(image.find_channel("var." + c));
    albedo.push_back(required(image, "feature.albedo." + c));
  }
  const std::array<const char*, kDenoiseFeatures> names{"feature.albedo",    "feature.N.X",       "feature.N.Y",
                                                        "feature.N.Z",       "feature.Z",         "feature.sun",
                                                        "feature.class.sky", "feature.class.leaf"};
  std::array<int, kDenoiseFeatures> feature{}, feature_var{};
  for (int f = 1; f < kDenoiseFeatures; ++f) {
    feature[f] = required(image, names[f]);
    feature_var[f] = image.find_channel(std::string("var.") + names[f]);
  }
  const int labels = image.find_channel("id.object");
  DenoiseBuffers b;
  b.width = image.width;
  b.height = image.height;
  b.channels = nc;
  const size_t pixels = static_cast<size_t>(image.width) * static_cast<size_t>(image.height);
  for (auto& h : b.half) h.resize(pixels * nc);
  b.variance.resize(pixels * nc);
  b.features.resize(pixels * kDenoiseFeatures);
  b.feature_variance.assign(pixels * kDenoiseFeatures, 0.0f);
  if (labels >= 0) b.labels.resize(pixels);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const size_t p = static_cast<size_t>(y) * image.width + x;
      double mean_albedo = 0;
      for (int c = 0; c < nc; ++c) {
        b.half[0][p * nc + c] = image.at(x, y, even[c]);
        b.half[1][p * nc + c] = image.at(x, y, odd[c]);
        b.variance[p * nc + c] = image.at(x, y, var[c]);
        mean_albedo += image.at(x, y, albedo[c]);
      }
      float* f = &b.features[p * kDenoiseFeatures];
      f[kFeatureAlbedo] = static_cast<float>(mean_albedo / nc);
      for (int k = 1; k < kDenoiseFeatures; ++k) {
        f[k] = image.at(x, y, feature[k]);
        if (feature_var[k] >= 0) b.feature_variance[p * kDenoiseFeatures + k] = image.at(x, y, feature_var[k]);
      }
      if (labels >= 0) b.labels[p] = static_cast<uint32_t>(image.at(x, y, labels));
    }
  return b;
}

Image denoise_image(const Image& image, const DenoiseSettings& settings, DenoiseStats* stats) {
  const DenoiseBuffers buffers = denoise_buffers(image);
  const std::vector<float> clean = denoise(buffers, settings, stats);
  const std::vector<std::string> channels = denoisable_channels(image);
  Image out = image;
  const int nc = static_cast<int>(channels.size());
  for (int c = 0; c < nc; ++c) {
    const int beauty = out.find_channel(channels[c]);
    out.add_channel("noisy." + channels[c], out.types[beauty]);
    const int noisy = out.channel_count() - 1;
    for (int y = 0; y < out.height; ++y)
      for (int x = 0; x < out.width; ++x) {
        out.at(x, y, noisy) = out.at(x, y, beauty);
        out.at(x, y, beauty) = clean[(static_cast<size_t>(y) * out.width + x) * nc + c];
      }
  }
  std::string radii;
  for (const int r : settings.radii) {
    if (!radii.empty()) radii += ',';
    radii += std::to_string(r);
  }
  out.set_attribute("sylva:denoised", kDenoiserName);
  out.set_attribute("sylva:denoise_settings",
                    fmt::format("radii {} color_k {} feature_scale {} ridge {} selection_radius {}", radii,
                                settings.color_k, settings.feature_scale, settings.ridge, settings.selection_radius));
  return out;
}

}  // namespace sylva
