#pragma once
// Checks of a command's output files before any work, so a mistake costs no rendering time and
// never destroys an input. Paths are compared after resolving symlinks, `.` and `..`
// (std::filesystem::weakly_canonical), so `-o link-to-scene.toml` is caught like `-o scene.toml`.
//
// Policy (docs/robustness.md): outputs are regular files. An existing output that is a device, a
// FIFO, a socket or a directory is refused (writing would replace it by a regular file, and as root
// `-o /dev/null` would replace /dev/null). An output that is a symlink is written through: the
// file it points to is replaced atomically (core/atomic_file.h) and the link is kept.

#include <filesystem>
#include <string>
#include <vector>

namespace sylva {

struct OutputFile {
  std::string option;  // how the user named it, for messages: "-o", "--png", "--obj"
  std::filesystem::path path;
};

// Throws sylva::Error naming the option unless every non-empty output
//  - differs from every input and from every other output (after resolving symlinks),
//  - is not an existing non-regular file,
//  - lies in an existing directory this process may create files in,
//  - has a file name the file system accepts (at most NAME_MAX bytes).
void check_outputs(const std::vector<OutputFile>& outputs, const std::vector<std::filesystem::path>& inputs);

// The path a write to `path` replaces: symlinks resolved, absolute (weakly_canonical, so a file that
// does not exist yet resolves through its existing parent directories).
std::filesystem::path resolved_output(const std::filesystem::path& path);

}  // namespace sylva
