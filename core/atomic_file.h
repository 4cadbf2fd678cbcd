#pragma once
// Atomic file output. Every file Sylva writes (images, previews, meshes, checkpoints, reports, golden
// records) goes through here: the bytes go to a temporary file in the target's directory, are flushed
// to disk (fsync), and the temporary is renamed over the target. A reader, an interrupted run or a full
// disk therefore never leaves a half-written file under the target's name. On any failure the
// temporary is removed, the previous target (if any) is left as it was, and a sylva::Error whose
// message starts with the target's path is thrown.
//
// Temporaries are named ".sylva-<pid>-<n>.tmp", n counting the writes of the process: hidden, unique
// per process and thread, and short, so any target name the file system accepts still works. They
// are created exclusively (O_CREAT | O_EXCL), so concurrent writers never share one; when several
// write the same target at once, the target ends as one writer's complete file.
//
// A target that is a symlink is written through (the file it points to is replaced, the link kept);
// a target that exists and is not a regular file (device, FIFO, directory) is refused with
// sylva::Error before anything is written (core/output_paths.h).

#include <filesystem>
#include <functional>
#include <ostream>
#include <string_view>

namespace sylva {

// Prefix of every temporary file name (tests check that none is left behind).
inline constexpr std::string_view kAtomicTempPrefix = ".sylva-";

// Writes `path` with `write(out)`, `out` a binary stream on the temporary. An exception from `write`
// aborts the write (a sylva::Error passes through unchanged, any other std::exception becomes
// sylva::Error("path: what")), as does a failed stream.
void write_file_atomic(const std::filesystem::path& path, const std::function<void(std::ostream& out)>& write);

// For libraries that write by file name (OpenEXR, libpng through a FILE): `write(temp)` writes the whole file at
// `temp`, an existing empty file it may truncate, then the file is committed as by write_file_atomic.
void write_file_atomic_by_name(const std::filesystem::path& path,
                               const std::function<void(const std::filesystem::path& temp)>& write);

}  // namespace sylva
