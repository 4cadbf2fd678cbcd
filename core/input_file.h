#pragma once
// Reading untrusted input files (scenes, species, tables, meshes, images) safely: only regular
// files are read (a FIFO, a device such as /dev/zero, a directory or a socket is refused instead of
// hanging or reading forever), opened without blocking, and never past a size limit. docs/limits.md
// lists the limits.

#include <cstdint>
#include <filesystem>
#include <string>

namespace sylva {

// Size limits of the text inputs (bytes).
inline constexpr uint64_t kMaxSceneFileBytes = uint64_t{64} << 20;    // scene files
inline constexpr uint64_t kMaxSpeciesFileBytes = uint64_t{64} << 20;  // species files and templates
inline constexpr uint64_t kMaxTableFileBytes = uint64_t{256} << 20;   // spectrum and SRF tables
inline constexpr uint64_t kMaxMeshFileBytes = uint64_t{16} << 30;     // OBJ and PLY meshes (mapped)

// Throws ParseError(file, 0, why) unless `file` names an existing regular file (after symlinks).
// `what` names the kind of file in the message ("scene file", "mesh", ...).
void require_regular_file(const std::filesystem::path& file, const std::string& what);

// The whole content of a regular file of at most `max_bytes` bytes. Opens with O_NONBLOCK and checks
// the opened descriptor (fstat), so a FIFO or device swapped in after a check is refused too.
// Throws ParseError(file, 0, why): cannot open, not a regular file, larger than the limit.
std::string read_input_file(const std::filesystem::path& file, uint64_t max_bytes, const std::string& what);

// FNV-1a 64 (core/hash.h) of a regular file's bytes, read in pieces (no copy of the whole file).
uint64_t fnv1a64_of_file(const std::filesystem::path& file, uint64_t max_bytes, const std::string& what);

// Opens `file` read-only for the caller after the same checks (regular file, at most `max_bytes`);
// returns the descriptor (close it) and sets `size` to the file's size. Throws like read_input_file.
int open_input_file(const std::filesystem::path& file, uint64_t max_bytes, const std::string& what, uint64_t& size);

}  // namespace sylva
