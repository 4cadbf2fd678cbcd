#include "core/output_paths.h"

#include "core/error.h"

#include <fmt/core.h>

#include <cerrno>
#include <climits>
#include <cstring>
#include <system_error>

#include <sys/stat.h>
#include <unistd.h>

namespace sylva {

namespace fs = std::filesystem;

fs::path resolved_output(const fs::path& path) {
  std::error_code ec;
  fs::path p = fs::absolute(path, ec);
  // Follow the file's own symlinks, dangling ones included (weakly_canonical keeps a dangling
  // link's name), at most as deep as the kernel does (ELOOP after 40).
  for (int depth = 0; depth < 40 && fs::is_symlink(p, ec); ++depth) {
    const fs::path to = fs::read_symlink(p, ec);
    if (ec) break;
    p = to.is_absolute() ? to : p.parent_path() / to;
  }
  const fs::path resolved = fs::weakly_canonical(p, ec);
  return ec ? p.lexically_normal() : resolved;
}

void check_outputs(const std::vector<OutputFile>& outputs, const std::vector<fs::path>& inputs) {
  std::vector<fs::path> resolved_inputs;
  for (const fs::path& in : inputs)
    if (!in.empty()) resolved_inputs.push_back(resolved_output(in));
  std::vector<std::pair<const OutputFile*, fs::path>> seen;
  for (const OutputFile& out : outputs) {
    if (out.path.empty()) continue;
    const std::string name = fmt::format("{} {}", out.option, out.path.string());
    const fs::path target = resolved_output(out.path);
    for (size_t i = 0; i < inputs.size(); ++i)
      if (!inputs[i].empty() && resolved_output(inputs[i]) == target)
        throw Error(fmt::format("{}: is the input {}; refusing to overwrite an input", name, inputs[i].string()));
    for (const auto& [other, other_target] : seen)
      if (other_target == target)
        throw Error(fmt::format("{}: the same file as {} {}; give each output its own file", name, other->option,
                                other->path.string()));
    seen.emplace_back(&out, target);

    struct stat st {};
    if (::stat(target.c_str(), &st) == 0 && !S_ISREG(st.st_mode))
      throw Error(fmt::format("{}: exists and is {}; outputs must be regular files (docs/robustness.md)", name,
                              S_ISDIR(st.st_mode)    ? "a directory"
                              : S_ISFIFO(st.st_mode) ? "a FIFO"
                              : S_ISSOCK(st.st_mode) ? "a socket"
                                                     : "a device"));
    if (target.filename().string().size() > NAME_MAX)
      throw Error(fmt::format("{}: the file name is longer than {} bytes", name, NAME_MAX));
    const fs::path dir = target.parent_path();
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) throw Error(fmt::format("{}: directory {} does not exist", name, dir.string()));
    if (::access(dir.c_str(), W_OK | X_OK) != 0)
      throw Error(fmt::format("{}: cannot create files in {}: {}", name, dir.string(), std::strerror(errno)));
  }
}

}  // namespace sylva
