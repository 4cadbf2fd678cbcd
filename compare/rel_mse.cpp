#include "compare/rel_mse.h"

#include "core/error.h"

#include <fmt/core.h>

#include <limits>

namespace sylva {

namespace {

struct Rows {
  int begin, end;
};

Rows counted_rows(const Image& ref, const RelMseOptions& o) {
  const Rows rows{o.row_begin, o.row_end < 0 ? ref.height : o.row_end};
  if (rows.begin < 0 || rows.begin >= rows.end || rows.end > ref.height)
    throw Error(fmt::format("rows {}:{} are not inside the reference (height {})", rows.begin, rows.end, ref.height));
  return rows;
}

int channel_of(const Image& image, const std::string& name, const char* which) {
  const int c = image.find_channel(name);
  if (c < 0) throw Error(fmt::format("the {} has no channel {}", which, name));
  return c;
}

// ε_c over the rows counted.
double epsilon_of(const Image& ref, int c, Rows rows, const RelMseOptions& o) {
  double sum = 0, sum_sq = 0;
  for (int y = rows.begin; y < rows.end; ++y)
    for (int x = 0; x < ref.width; ++x) {
      const double r = ref.at(x, y, c);
      sum += r;
      sum_sq += r * r;
    }
  const double n = static_cast<double>(ref.width) * (rows.end - rows.begin);
  const double mean = sum / n;
  return o.epsilon_scale * (o.epsilon == RelMseEpsilon::mean_square ? sum_sq / n : mean * mean);
}

}  // namespace

std::vector<double> relative_squared_errors(const Image& test, const Image& ref, const RelMseOptions& o) {
  if (test.width != ref.width || test.height != ref.height)
    throw Error(fmt::format("the image is {}x{}, the reference {}x{}", test.width, test.height, ref.width, ref.height));
  if (o.channels.empty()) throw Error("no channels to compare");
  const Rows rows = counted_rows(ref, o);
  std::vector<double> errors(static_cast<size_t>(ref.width) * static_cast<size_t>(rows.end - rows.begin), 0.0);
  for (const std::string& name : o.channels) {
    const int tc = channel_of(test, name, "image"), rc = channel_of(ref, name, "reference");
    const int vc = o.subtract_reference_variance ? channel_of(ref, "var." + name, "reference") : -1;
    const double eps = epsilon_of(ref, rc, rows, o);
    size_t i = 0;
    for (int y = rows.begin; y < rows.end; ++y)
      for (int x = 0; x < ref.width; ++x, ++i) {
        const double r = ref.at(x, y, rc), d = static_cast<double>(test.at(x, y, tc)) - r;
        const double e = d * d - (vc >= 0 ? ref.at(x, y, vc) : 0.0);
        const double denominator = r * r + eps;  // 0 only where the reference's channel is black throughout
        errors[i] += denominator > 0 ? e / denominator : (e == 0 ? 0.0 : std::numeric_limits<double>::infinity());
      }
  }
  for (double& e : errors) e /= static_cast<double>(o.channels.size());
  return errors;
}

double relative_mse(const Image& test, const Image& ref, const RelMseOptions& options) {
  const std::vector<double> errors = relative_squared_errors(test, ref, options);
  double sum = 0;
  for (const double e : errors) sum += e;
  return sum / static_cast<double>(errors.size());
}

std::vector<std::string> beauty_channels(const Image& ref) {
  std::vector<std::string> names;
  for (const std::string& name : ref.channels) {
    bool derived = false;
    for (const char* prefix : {"var.", "noisy.", "even.", "odd.", "albedo.", "feature."})
      derived = derived || name.rfind(prefix, 0) == 0;
    if (!derived && ref.find_channel("var." + name) >= 0) names.push_back(name);
  }
  return names;
}

}  // namespace sylva
