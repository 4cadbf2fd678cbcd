// The HTML report of a comparison in a real browser: headless Chromium (Debian `chromium`) loads
// the report of a local failure, and a script run after the page's load event finds every image
// decoded (complete, with its natural size) and the failing region listed. Skipped, saying why,
// where Chromium is not installed; the README's test command installs it (cmake/install-deps.sh)
// and sets SYLVA_REQUIRE_CHROMIUM=1, which turns that skip into a failure.

#include "compare/compare_report.h"
#include "compare/image_compare.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

namespace sylva {
namespace report_browser_test {
namespace {

namespace fs = std::filesystem;

// The browser on PATH, or "".
std::string find_chromium() {
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path != nullptr ? path : "");
  for (std::string dir; std::getline(dirs, dir, ':');)
    for (const char* name : {"chromium", "chromium-browser"})
      if (!dir.empty() && fs::exists(fs::path(dir) / name)) return (fs::path(dir) / name).string();
  return {};
}

// 64×64 R,G,B with variance and ids: a square "object" 7 (class 3) in the middle, `scale` times
// brighter in the test.
Image draw(int spp, double scale, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  Image image = make_image(64, 64, {"R", "G", "B", "var.R", "var.G", "var.B"});
  for (const char* id : {"id.instance", "id.object", "id.class"}) image.add_channel(id, PixelType::UInt);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      const bool object = x >= 20 && x < 36 && y >= 24 && y < 40;
      for (int c = 0; c < 3; ++c) {
        const double mu = object ? 0.3 * scale : 0.1 + 0.2 * c, var = std::pow(0.5 * mu, 2) / spp;
        image.at(x, y, c) = static_cast<float>(mu + normal(rng) * std::sqrt(var));
        image.at(x, y, 3 + c) = static_cast<float>(var);
      }
      image.at(x, y, 6) = object ? 2.0f : 1.0f;
      image.at(x, y, 7) = object ? 7.0f : 1.0f;
      image.at(x, y, 8) = object ? 3.0f : 1.0f;
    }
  image.attributes = {{"sylva:spp", std::to_string(spp)}};
  return image;
}

std::string read_text(const fs::path& p) {
  std::stringstream s;
  s << std::ifstream(p).rdbuf();
  return s.str();
}

// Loads `page` in headless Chromium and returns the probe's line ("PROBE images=… broken=… […]
// regions=…"), or a failure.
std::string load_in_chromium(const std::string& chromium, const fs::path& dir, const fs::path& page) {
  const fs::path dom = dir / "dom.html", log = dir / "chromium.log";
  const std::string cmd = "timeout 120 '" + chromium +
                          "' --headless --no-sandbox --disable-gpu --no-first-run --user-data-dir='" +
                          (dir / "profile").string() + "' --virtual-time-budget=10000 --dump-dom 'file://" +
                          page.string() + "' >'" + dom.string() + "' 2>'" + log.string() + "'";
  if (std::system(cmd.c_str()) != 0) {
    ADD_FAILURE() << "chromium failed: " << read_text(log);
    return {};
  }
  const std::string out = read_text(dom);
  const std::string mark = "<pre id=\"probe\">";
  const size_t at = out.find(mark);
  if (at == std::string::npos) {
    ADD_FAILURE() << "the page did not finish loading:\n" << out.substr(0, 2000) << read_text(log);
    return {};
  }
  return out.substr(at + mark.size(), out.find('<', at + mark.size()) - at - mark.size());
}

class ReportBrowser : public test::TempDirTest {};

TEST_F(ReportBrowser, ChromiumLoadsTheReportWithEveryImage) {
  const std::string chromium = find_chromium();
  if (chromium.empty()) {
    // The README's test command installs Chromium and sets SYLVA_REQUIRE_CHROMIUM, so there a
    // missing browser is a failure, never a skip that reads as done.
    const char* required = std::getenv("SYLVA_REQUIRE_CHROMIUM");
    if (required != nullptr && std::string(required) == "1")
      FAIL() << "Chromium is not on PATH, but SYLVA_REQUIRE_CHROMIUM=1 (cmake/build-and-test.sh) requires it";
    GTEST_SKIP() << "Chromium is not installed (Debian package chromium; cmake/install-deps.sh installs it): "
                    "the HTML report was not loaded in a browser";
  }
  const fs::path dir = dir_;
  const Image ref = draw(4096, 1.0, 1), test = draw(64, 1.06, 2);
  const CompareResult r = compare_images(test, ref, {});
  ASSERT_FALSE(r.passed);
  write_compare_report(dir / "report", test, ref, r);

  // The report with a probe appended: after the load event it writes what it found into the DOM,
  // which --dump-dom prints.
  std::string html = read_text(dir / "report" / "index.html");
  const std::string probe =
      "<script>window.addEventListener('load', () => {"
      "const imgs = [...document.images];"
      "const bad = imgs.filter(i => !i.complete || i.naturalWidth === 0).map(i => i.getAttribute('src'));"
      "const p = document.createElement('pre'); p.id = 'probe';"
      "p.textContent = 'PROBE images=' + imgs.length + ' broken=' + bad.length + ' [' + bad.join(',') + ']"
      " regions=' + (document.getElementById('regions') ? document.getElementById('regions').rows.length - 1 : -1);"
      "document.body.appendChild(p); });</script>\n";
  html.insert(html.rfind("</body>"), probe);
  std::ofstream(dir / "report" / "probe.html") << html;

  // rgb and the three ids: four previews each; every one decoded, the failing object listed.
  const std::string line = load_in_chromium(chromium, dir, dir / "report" / "probe.html");
  std::printf("[browser] %s\n", line.c_str());
  EXPECT_NE(line.find("images=16 broken=0 []"), std::string::npos) << line;
  EXPECT_EQ(line.find("regions=0"), std::string::npos) << line;
  EXPECT_EQ(line.find("regions=-1"), std::string::npos) << line;
  EXPECT_NE(read_text(dir / "report" / "index.html").find("object 7"), std::string::npos);
  // The probe can fail: a preview removed is reported broken.
  fs::remove(dir / "report" / "rgb_diff.png");
  const std::string missing = load_in_chromium(chromium, dir, dir / "report" / "probe.html");
  EXPECT_NE(missing.find("broken=1 [rgb_diff.png]"), std::string::npos) << missing;
}

}  // namespace
}  // namespace report_browser_test
}  // namespace sylva
