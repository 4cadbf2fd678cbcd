// Issue 16 end to end, as a careless or hostile user would try it: outputs that are inputs (or each
// other), devices, FIFOs and symlinks as outputs; inputs that are not regular files; resumes into a
// changed scene or from a corrupt checkpoint; numbers that are NaN, infinite or overflow; hangs and
// signals during loading; checks before rendering (view, directories, memory); and no samples lost
// when an output cannot be written. Each test failed on the code before the issue was fixed.

#include "core/image.h"
#include "tests/support/run_command.h"
#include "tests/support/sanitizer.h"

#include <gtest/gtest.h>

#include <signal.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>

#include <chrono>
#include <fstream>
#include <thread>

namespace sylva {
namespace {

namespace fs = std::filesystem;
using test::fresh_dir;
using test::q;
using test::read_text;
using test::run_sylva;

void write(const fs::path& file, const std::string& text) { std::ofstream(file, std::ios::binary) << text; }

// A small scene reading a spectrum table and an OBJ mesh beside it.
fs::path make_scene(const fs::path& dir) {
  write(dir / "refl.csv", "lambda_nm,r\n300,0.3\n2600,0.4\n");
  write(dir / "quad.obj", "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3 4\n");
  write(dir / "s.toml", R"([render]
width = 32
height = 24
spp = 4
[camera]
position = [0, -4, 3]
target = [0, 0, 0]
[sun]
elevation = 40
[materials.soil]
reflectance = { file = "refl.csv", column = "r" }
[[meshes]]
file = "quad.obj"
material = "soil"
scale = 4
[[meshes]]
shape = "box"
size = [1, 1, 1]
material = "soil"
)");
  return dir / "s.toml";
}

// Starts `args` (a sylva command line, stderr to `log`) in the background; returns its pid.
pid_t start_sylva(const std::string& args, const fs::path& log) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    const std::string cmd = "exec '" + std::string(SYLVA_BINARY) + "' " + args + " 2>'" + log.string() + "'";
    ::execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  return pid;
}

bool wait_for_text(const fs::path& log, const std::string& text, double seconds) {
  for (int i = 0; i < seconds * 20; ++i) {
    if (read_text(log).find(text) != std::string::npos) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return false;
}

int wait_exit_code(pid_t pid) {
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
}

// An interrupted render of `scene` at `out` (dir/out.exr by default): leaves its checkpoint
// (asserted by the caller).
int interrupted_render(const fs::path& dir, const fs::path& scene, const std::string& options, fs::path out = {}) {
  const fs::path log = dir / "interrupted.txt";
  if (out.empty()) out = dir / "out.exr";
  const pid_t pid = start_sylva("render " + q(scene) + " -o " + q(out) + options, log);
  EXPECT_TRUE(wait_for_text(log, "scene:", 30)) << read_text(log);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  ::kill(pid, SIGINT);
  return wait_exit_code(pid);
}

TEST(CliRobustness, OutputsThatAreInputsOrEachOtherAreRefused) {
  const fs::path dir = fresh_dir("robust_alias");
  const fs::path scene = make_scene(dir);
  const std::string scene_text = read_text(scene);
  fs::copy_file(SYLVA_SOURCE_DIR "/data/species/quaking_aspen.toml", dir / "sp.toml");
  const std::string species_text = read_text(dir / "sp.toml");
  fs::create_symlink(scene, dir / "link.exr");
  struct Case {
    std::string args, expected;
  };
  const Case cases[] = {
      {"render " + q(scene) + " -o " + q(scene), "is the input"},
      {"render " + q(scene) + " -o " + q(dir / "link.exr"), "is the input"},
      {"render " + q(scene) + " -o " + q(dir / "o.exr") + " --png " + q(dir / "o.exr"), "the same file as -o"},
      {"render " + q(scene) + " -o " + q(dir / "quad.obj"), "is the input"},
      {"render " + q(scene) + " -o " + q(dir / "x.exr") + " --png " + q(dir / "refl.csv"), "is the input"},
      {"export " + q(scene) + " --obj " + q(scene), "is the input"},
      {"merge " + q(scene) + " -o " + q(scene), "is the input"},
      {"export " + q(scene) + " --obj " + q(dir / "quad.obj"), "is the input"},
      {"tree " + q(dir / "sp.toml") + " --obj " + q(dir / "sp.toml"), "is the input"},
      {"tree " + q(dir / "sp.toml") + " --obj " + q(dir / "t.obj") + " --ply " + q(dir / "t.obj"), "the same file"},
  };
  for (const Case& c : cases) {
    const auto r = run_sylva(c.args, dir);
    EXPECT_EQ(r.exit_code, 2) << c.args;
    EXPECT_NE(r.err.find(c.expected), std::string::npos) << c.args << "\n" << r.err;
  }
  EXPECT_EQ(read_text(scene), scene_text);
  EXPECT_EQ(read_text(dir / "sp.toml"), species_text);
  EXPECT_TRUE(fs::is_symlink(dir / "link.exr"));
  EXPECT_FALSE(fs::exists(dir / "o.exr"));
}

TEST(CliRobustness, FifoAndDeviceOutputsAreRefusedSymlinkedOutputsWrittenThrough) {
  const fs::path dir = fresh_dir("robust_special_out");
  const fs::path scene = make_scene(dir);
  ASSERT_EQ(::mkfifo((dir / "fifo.exr").c_str(), 0600), 0);
  auto r = run_sylva("render " + q(scene) + " -q -o " + q(dir / "fifo.exr"), dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("exists and is a FIFO"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::is_fifo(dir / "fifo.exr"));
  // A character device like /dev/null (mknod needs privileges; root in CI).
  if (::mknod((dir / "null").c_str(), S_IFCHR | 0666, makedev(1, 3)) == 0) {
    r = run_sylva("export " + q(scene) + " -q --obj " + q(dir / "null"), dir);
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("exists and is a device"), std::string::npos) << r.err;
    EXPECT_TRUE(fs::is_character_file(dir / "null"));
  }
  fs::create_directory(dir / "real");
  fs::create_symlink(dir / "real" / "out.exr", dir / "link.exr");
  r = run_sylva("render " + q(scene) + " -q -o " + q(dir / "link.exr"), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::is_symlink(dir / "link.exr"));
  EXPECT_EQ(read_exr(dir / "real" / "out.exr").width, 32);
}

TEST(CliRobustness, ConcurrentExportsToOneFileLeaveOneCompleteFile) {
  const fs::path dir = fresh_dir("robust_race");
  const std::string species = SYLVA_SOURCE_DIR "/data/species/abop_bush.lsys";
  for (int seed : {1, 2})
    ASSERT_EQ(run_sylva("tree " + species + " --seed " + std::to_string(seed) + " --obj " +
                            q(dir / ("seed" + std::to_string(seed) + ".obj")),
                        dir)
                  .exit_code,
              0);
  for (int attempt = 0; attempt < 3; ++attempt) {
    const std::string b = "'" + std::string(SYLVA_BINARY) + "' tree " + species + " --obj " + q(dir / "same.obj");
    ASSERT_EQ(std::system(("cd " + q(dir) + " && (" + b + " --seed 1 & " + b + " --seed 2 & wait)").c_str()), 0);
    const std::string both = read_text(dir / "same.obj");
    EXPECT_TRUE(both == read_text(dir / "seed1.obj") || both == read_text(dir / "seed2.obj")) << "mixed output";
  }
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path().filename().string().rfind(".sylva-", 0), std::string::npos) << "temporary left";
}

TEST(CliRobustness, InputsThatAreNotRegularFilesAreRefusedAtOnce) {
  const fs::path dir = fresh_dir("robust_special_in");
  ASSERT_EQ(::mkfifo((dir / "fifo").c_str(), 0600), 0);
  fs::create_directory(dir / "scene_dir.toml");
  const auto start = std::chrono::steady_clock::now();
  struct Case {
    std::string args, expected;
  };
  const Case cases[] = {
      {"render " + q(dir / "scene_dir.toml") + " -o " + q(dir / "o.exr"), "a directory"},
      {"render " + q(dir / "fifo") + " -o " + q(dir / "o.exr"), "a FIFO"},
      {"render /dev/zero -o " + q(dir / "o.exr"), "a device"},
      {"export " + q(dir / "fifo") + " --obj " + q(dir / "o.obj"), "a FIFO"},
      {"tree " + q(dir / "fifo"), "cannot read species file: a FIFO"},
      {"compare " + q(dir / "fifo") + " /dev/zero", "a FIFO"},
      {"compare " + std::string(SYLVA_SOURCE_DIR) + "/golden/ground_sun.exr /dev/zero", "a device"},
  };
  for (const Case& c : cases) {
    const auto r = run_sylva(c.args, dir);
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.expected), std::string::npos) << c.args << "\n" << r.err;
  }
  ASSERT_EQ(::mkfifo((dir / "fifo_tree.toml").c_str(), 0600), 0);
  const auto r = run_sylva("tree " + q(dir / "fifo_tree.toml"), dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("cannot read species file: a FIFO"), std::string::npos) << r.err;
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(60)) << "nothing may wait for a writer";
}

TEST(CliRobustness, NumbersThatAreNanInfiniteOrOverflowAreRefused) {
  const fs::path dir = fresh_dir("robust_numbers");
  const fs::path scene = make_scene(dir);
  const std::string render = "render " + q(scene) + " -q -o " + q(dir / "o.exr");
  const std::string ref = std::string(SYLVA_SOURCE_DIR) + "/golden/ground_sun.exr";
  const std::string tree = "tree " + std::string(SYLVA_SOURCE_DIR) + "/data/species/abop_bush.lsys";
  struct Case {
    std::string args, expected;
  };
  const Case cases[] = {
      {render + " --res 4294967360x36", "--res"},
      {render + " --res 65537x2", "--res"},
      {render + " --res -4x4", "--res"},
      {render + " --exposure nan", "--exposure"},
      {render + " --exposure inf", "--exposure"},
      {render + " --checkpoint-minutes nan", "--checkpoint-minutes"},
      {render + " --seed 18446744073709551616", "--seed"},
      {render + " --fps nan --frames 0:1", "--fps"},
      {tree + " --quality nan", "--quality"},
      {tree + " --seed 18446744073709551616", "--seed"},
      {tree + " --time inf", "--time"},
      {"compare " + ref + " " + ref + " --fail nan", "--fail"},
      {"compare " + ref + " " + ref + " --alpha nan", "--alpha"},
  };
  for (const Case& c : cases) {
    const auto r = run_sylva(c.args, dir);
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.expected), std::string::npos) << c.args << "\n" << r.err;
  }
  EXPECT_FALSE(fs::exists(dir / "o.exr"));
}

TEST(CliRobustness, ResumeRefusesAnEditedInputACorruptCheckpointAndFewerSamples) {
  const fs::path dir = fresh_dir("robust_resume");
  const fs::path scene = make_scene(dir);
  const std::string options = " --res 160x90 --spp 400 --threads 2";
  ASSERT_EQ(interrupted_render(dir, scene, options), 130) << read_text(dir / "interrupted.txt");
  const fs::path checkpoint = dir / "out.exr.checkpoint";
  ASSERT_TRUE(fs::exists(checkpoint));
  const std::string resume = "render " + q(scene) + " -q -o " + q(dir / "out.exr") + " --resume";
  // Fewer samples per pixel than the checkpoint holds.
  auto r = run_sylva(resume + " --res 160x90 --spp 1 --threads 2", dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("more than --spp 1"), std::string::npos) << r.err;
  // A corrupt checkpoint (one byte of the sums changed).
  const std::string good = read_text(checkpoint);
  std::string bad = good;
  bad[bad.size() / 2] = static_cast<char>(bad[bad.size() / 2] ^ 0x10);
  write(checkpoint, bad);
  r = run_sylva(resume + options, dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("corrupt checkpoint"), std::string::npos) << r.err;
  write(checkpoint, good);
  // The mesh and the spectrum table the scene reads, edited after the checkpoint.
  for (const char* input : {"quad.obj", "refl.csv"}) {
    const std::string original = read_text(dir / input);
    write(dir / input, original + "\n");
    r = run_sylva(resume + options, dir);
    EXPECT_EQ(r.exit_code, 2) << input;
    EXPECT_NE(r.err.find("different render"), std::string::npos) << input << ": " << r.err;
    write(dir / input, original);
  }
  // The unchanged scene resumes; the header's scene hash covers the inputs too.
  r = run_sylva(resume + options, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string hash = read_exr(dir / "out.exr").attribute("sylva:scene_hash");
  write(dir / "quad.obj", read_text(dir / "quad.obj") + "\n");
  ASSERT_EQ(run_sylva("render " + q(scene) + " -q -o " + q(dir / "edited.exr") + " --spp 1", dir).exit_code, 0);
  EXPECT_NE(read_exr(dir / "edited.exr").attribute("sylva:scene_hash"), hash);
}

TEST(CliRobustness, WillowWithSplittingClonesFinishesQuickly) {
  const fs::path dir = fresh_dir("robust_willow");
  std::string xml = read_text(SYLVA_SOURCE_DIR "/tests/data/arbaro/weeping_willow.xml");
  const std::string from = "name='1SegSplits' value='0.2'";
  ASSERT_NE(xml.find(from), std::string::npos);
  xml.replace(xml.find(from), from.size(), "name='1SegSplits' value='5'");
  write(dir / "willow.xml", xml);
  const auto start = std::chrono::steady_clock::now();
  const auto r = run_sylva("tree " + q(dir / "willow.xml"), dir);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("tree too large"), std::string::npos) << r.err;
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(60));
}

// Whether process `pid` catches signal `sig` (its handler is installed: the bit in SigCgt of
// /proc/PID/status), polled until `timeout`.
bool wait_until_catching(pid_t pid, int sig, std::chrono::seconds timeout) {
  const auto end = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < end) {
    std::ifstream status("/proc/" + std::to_string(pid) + "/status");
    for (std::string line; std::getline(status, line);)
      if (line.rfind("SigCgt:", 0) == 0 && (std::stoull(line.substr(7), nullptr, 16) >> (sig - 1) & 1u)) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

TEST(CliRobustness, SignalsDuringSceneLoadingEndTheProcessWithNonZeroStatus) {
  const fs::path dir = fresh_dir("robust_loading");
  // Slow to load: many distinct seeds of a large species, each generated and meshed.
  std::string text = "[materials.m]\nreflectance = 0.5\n";
  for (int seed = 1; seed <= 200; ++seed)
    text += "[[trees]]\nspecies = \"" SYLVA_SOURCE_DIR
            "/data/species/weeping_willow.toml\"\nbark = \"m\"\nleaf = \"m\"\n"
            "quality = 2\nseed = " +
            std::to_string(seed) + "\n";
  write(dir / "slow.toml", text);
  for (const int sig : {SIGTERM, SIGINT}) {
    const fs::path log = dir / "log.txt";
    const pid_t pid = start_sylva("render " + q(dir / "slow.toml") + " -o " + q(dir / "o.exr"), log);
    // Past start-up — once the process catches the signal (libraries load slowly on a busy
    // machine) — and well before the scene is loaded.
    ASSERT_TRUE(wait_until_catching(pid, sig, std::chrono::seconds(60))) << read_text(log);
    const auto signalled = std::chrono::steady_clock::now();
    ::kill(pid, sig);
    EXPECT_EQ(wait_exit_code(pid), 128 + sig) << read_text(log);
    EXPECT_LT(std::chrono::steady_clock::now() - signalled, std::chrono::seconds(5)) << "the signal was not acted on";
    EXPECT_EQ(read_text(log).find("scene:"), std::string::npos) << "the scene loaded within 3 s; make it slower";
    EXPECT_NE(read_text(log).find("interrupted"), std::string::npos) << read_text(log);
    EXPECT_FALSE(fs::exists(dir / "o.exr.checkpoint"));
  }
}

TEST(CliRobustness, EveryOutputAndOptionIsCheckedBeforeRendering) {
  const fs::path dir = fresh_dir("robust_precheck");
  const fs::path scene = make_scene(dir);
  // A render that would take minutes: each mistake must be reported at once.
  const std::string render = "render " + q(scene) + " -q --spp 100000";
  struct Case {
    std::string args, expected;
  };
  const Case cases[] = {
      {" --res 1920x1080 -o " + q(dir / "o.exr") + " --png " + q(dir / "o.png") + " --view Nope",
       "unknown preview view \"Nope\""},
      {" --res 1920x1080 -o " + q(dir / "missing" / "o.exr"), "does not exist"},
      {" --res 1920x1080 -o " + q(dir / "o.exr") + " --png " + q(dir / "missing" / "o.png"), "does not exist"},
      {" -o " + q(dir / "o.exr") + " --res 20000x20000", "GiB"},
  };
  for (const Case& c : cases) {
    const auto start = std::chrono::steady_clock::now();
    const auto r = run_sylva(render + c.args, dir);
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.expected), std::string::npos) << c.args << "\n" << r.err;
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(20)) << c.args;
  }
  // The memory estimate names the figure and the override.
  const auto big = run_sylva(render + " -o " + q(dir / "o.exr") + " --res 20000x20000", dir);
  EXPECT_NE(big.err.find("--no-memory-check"), std::string::npos) << big.err;
  EXPECT_FALSE(fs::exists(dir / "o.exr"));
}

// Under a 3 GB address-space limit a 4000x4000 image is refused before it is rendered.
TEST(CliRobustness, AnAddressSpaceLimitRefusesARenderBeforeItStarts) {
  if (test::kAddressSanitizer)
    GTEST_SKIP() << "AddressSanitizer reserves terabytes of shadow address space: sylva cannot start under "
                    "`ulimit -v` in this build";
  const fs::path dir = fresh_dir("robust_ulimit");
  const fs::path scene = make_scene(dir);
  const std::string render = "render " + q(scene) + " -q --spp 100000";
  const std::string limited = "sh -c \"ulimit -v 3000000; exec '" + std::string(SYLVA_BINARY) + "' " + render + " -o " +
                              q(dir / "o.exr") + " --res 4000x4000\"";
  const auto start = std::chrono::steady_clock::now();
  const int status = std::system((limited + " 2>" + q(dir / "limited.txt")).c_str());
  EXPECT_EQ(WEXITSTATUS(status), 2) << read_text(dir / "limited.txt");
  EXPECT_NE(read_text(dir / "limited.txt").find("GiB are available"), std::string::npos)
      << read_text(dir / "limited.txt");
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(20));
  EXPECT_FALSE(fs::exists(dir / "o.exr"));
}

TEST(CliRobustness, AnOutputThatCannotBeWrittenKeepsTheSamplesForResume) {
  const fs::path dir = fresh_dir("robust_lost");
  const fs::path scene = make_scene(dir);
  fs::create_directory(dir / "previews");
  const std::string options =
      " --res 160x90 --spp 200 --threads 2 -o " + q(dir / "out.exr") + " --png " + q(dir / "previews" / "out.png");
  // The preview's directory disappears while the render runs.
  const fs::path log = dir / "log.txt";
  const pid_t pid = start_sylva("render " + q(scene) + options, log);
  ASSERT_TRUE(wait_for_text(log, "scene:", 30)) << read_text(log);
  fs::remove_all(dir / "previews");
  EXPECT_EQ(wait_exit_code(pid), 2) << read_text(log);
  EXPECT_NE(read_text(log).find("the rendered samples are kept in"), std::string::npos) << read_text(log);
  ASSERT_TRUE(fs::exists(dir / "out.exr.checkpoint"));
  // Resumed, it only writes the outputs: the same bytes as an uninterrupted render.
  fs::create_directory(dir / "previews");
  const auto r = run_sylva("render " + q(scene) + options + " -q --resume", dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir / "previews" / "out.png"));
  EXPECT_FALSE(fs::exists(dir / "out.exr.checkpoint"));
  ASSERT_EQ(run_sylva("render " + q(scene) + " -q --res 160x90 --spp 200 --threads 2 -o " + q(dir / "ref.exr"), dir)
                .exit_code,
            0);
  EXPECT_EQ(read_text(dir / "out.exr"), read_text(dir / "ref.exr"));
}

TEST(CliRobustness, TooManyBandsAreAnErrorNotATermination) {
  // 70 user bands ended in "terminate called without an active exception" (issue 16).
  const fs::path dir = fresh_dir("robust_bands");
  std::string text = "[render]\nwidth = 16\nheight = 12\nspp = 2\nbands = [";
  for (int i = 0; i < 70; ++i) text += (i ? ", " : "") + ("\"b" + std::to_string(i) + "\"");
  text += "]\n";
  for (int i = 0; i < 70; ++i)
    text += "[[bands]]\nname = \"b" + std::to_string(i) + "\"\nresponse = { lambda_nm = [" +
            std::to_string(400 + 5 * i) + ", " + std::to_string(405 + 5 * i) + "], value = [1, 1] }\n";
  write(dir / "bands.toml", text);
  const auto r = run_sylva("render " + q(dir / "bands.toml") + " -q -o " + q(dir / "o.exr"), dir);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("too many band channels"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("terminate"), std::string::npos) << r.err;
}

TEST(CliRobustness, LongOutputNamesWork) {
  const fs::path dir = fresh_dir("robust_long");
  const fs::path scene = make_scene(dir);
  const fs::path out = dir / (std::string(246, 'n') + ".exr");  // 250 bytes
  const auto r = run_sylva("render " + q(scene) + " -q -o " + q(out), dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(out));
  // Its checkpoint's name is shortened with a hash, and an interrupted render of it resumes.
  ASSERT_EQ(interrupted_render(dir, scene, " --res 160x90 --spp 400 --threads 2", out), 130);
  std::vector<std::string> checkpoints;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".checkpoint") checkpoints.push_back(e.path().filename().string());
  ASSERT_EQ(checkpoints.size(), 1u);
  EXPECT_EQ(checkpoints[0].size(), 255u);
  const auto resumed =
      run_sylva("render " + q(scene) + " -q --res 160x90 --spp 400 --threads 2 --resume -o " + q(out), dir);
  EXPECT_EQ(resumed.exit_code, 0) << resumed.err;
}

TEST(CliRobustness, GoldenCheckOfNothingFails) {
  const fs::path dir = fresh_dir("robust_golden");
  fs::create_directories(dir / "empty" / "scenes");
  const auto r = run_sylva("golden check --dir " + q(dir / "empty"), dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("no golden cases"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace sylva
