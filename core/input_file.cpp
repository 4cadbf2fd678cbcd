#include "core/input_file.h"

#include "core/error.h"
#include "core/hash.h"

#include <fmt/core.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <vector>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace sylva {

namespace {

std::string kind_of(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode) || S_ISBLK(mode)) return "a device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

}  // namespace

void require_regular_file(const std::filesystem::path& file, const std::string& what) {
  struct stat st {};
  if (::stat(file.c_str(), &st) != 0)
    throw ParseError(file, 0, fmt::format("cannot open {}: {}", what, std::strerror(errno)));
  if (!S_ISREG(st.st_mode)) throw ParseError(file, 0, fmt::format("cannot read {}: {}", what, kind_of(st.st_mode)));
}

int open_input_file(const std::filesystem::path& file, uint64_t max_bytes, const std::string& what, uint64_t& size) {
  // O_NONBLOCK: opening a FIFO without a writer would otherwise wait forever.
  const int fd = ::open(file.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw ParseError(file, 0, fmt::format("cannot open {}: {}", what, std::strerror(errno)));
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    const std::string kind = kind_of(st.st_mode);
    ::close(fd);
    throw ParseError(file, 0, fmt::format("cannot read {}: {}", what, kind));
  }
  size = static_cast<uint64_t>(st.st_size);
  if (size > max_bytes) {
    ::close(fd);
    throw ParseError(
        file, 0,
        fmt::format("{} of {} bytes is larger than the limit of {} bytes (docs/limits.md)", what, size, max_bytes));
  }
  ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
  return fd;
}

namespace {

// Reads the file opened as `fd` (`size` bytes when opened) into `chunk(data, n)` pieces of at most
// `buffer_bytes`, retrying interrupted reads, then closes it. A file that grows while read is cut at
// its size when opened; one that shrinks ends early. Returns the bytes read.
template <typename Chunk>
uint64_t read_chunks(int fd, uint64_t size, char* buffer, size_t buffer_bytes, const std::filesystem::path& file,
                     const std::string& what, Chunk&& chunk) {
  uint64_t done = 0;
  while (done < size) {
    const ssize_t n = ::read(fd, buffer, static_cast<size_t>(std::min<uint64_t>(buffer_bytes, size - done)));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const int err = errno;
      ::close(fd);
      throw ParseError(file, 0, fmt::format("cannot read {}: {}", what, std::strerror(err)));
    }
    if (n == 0) break;
    chunk(buffer, static_cast<size_t>(n));
    done += static_cast<uint64_t>(n);
  }
  ::close(fd);
  return done;
}

}  // namespace

uint64_t fnv1a64_of_file(const std::filesystem::path& file, uint64_t max_bytes, const std::string& what) {
  uint64_t size = 0;
  const int fd = open_input_file(file, max_bytes, what, size);
  Fnv1a64 hash;
  std::vector<char> buffer(size_t{1} << 20);
  read_chunks(fd, size, buffer.data(), buffer.size(), file, what,
              [&](const char* data, size_t n) { hash.add(data, n); });
  return hash.value();
}

std::string read_input_file(const std::filesystem::path& file, uint64_t max_bytes, const std::string& what) {
  uint64_t size = 0;
  const int fd = open_input_file(file, max_bytes, what, size);
  std::string text(static_cast<size_t>(size), '\0');
  std::string chunk_buffer(size_t{1} << 20, '\0');
  size_t done = 0;
  read_chunks(fd, size, chunk_buffer.data(), chunk_buffer.size(), file, what, [&](const char* data, size_t n) {
    std::memcpy(text.data() + done, data, n);
    done += n;
  });
  text.resize(done);
  return text;
}

}  // namespace sylva
