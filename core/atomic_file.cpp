#include "core/atomic_file.h"

#include "core/error.h"
#include "core/output_paths.h"

#include <fmt/core.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <streambuf>
#include <string>
#include <system_error>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace sylva {
namespace {

namespace fs = std::filesystem;

std::atomic<uint64_t> g_temporaries{0};

// The temporary beside a target: created exclusively, removed unless committed.
class Temporary {
 public:
  explicit Temporary(const fs::path& target) : target_(target), resolved_(resolved_output(target)) {
    struct stat st {};
    if (::stat(resolved_.c_str(), &st) == 0 && !S_ISREG(st.st_mode))
      throw Error(target.string() + ": exists and is not a regular file; outputs must be regular files");
    const unsigned long pid = static_cast<unsigned long>(::getpid());
    for (;;) {
      path_ = resolved_.parent_path() / fmt::format("{}{}-{}.tmp", kAtomicTempPrefix, pid, g_temporaries.fetch_add(1));
      fd_ = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
      if (fd_ >= 0) return;
      // A name left by a crashed process with the same pid is skipped; anything else is fatal.
      if (errno != EEXIST) fail("cannot create a temporary file", errno);
    }
  }
  Temporary(const Temporary&) = delete;
  Temporary& operator=(const Temporary&) = delete;
  ~Temporary() {
    if (fd_ >= 0) ::close(fd_);
    if (!committed_) {
      std::error_code ignored;
      fs::remove(path_, ignored);
    }
  }

  const fs::path& path() const { return path_; }
  int fd() const { return fd_; }

  // Closes the descriptor this object opened, reporting a deferred write error.
  void close() {
    if (fd_ < 0) return;
    const int rc = ::close(fd_);
    fd_ = -1;
    if (rc != 0) fail("cannot write", errno);
  }

  // Flushes the temporary's bytes to disk and renames it over the target.
  void commit() {
    close();
    const int fd = ::open(path_.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) fail("cannot reopen the temporary file", errno);
    const int rc = ::fsync(fd);
    const int err = errno;
    ::close(fd);
    if (rc != 0) fail("cannot flush to disk", err);
    std::error_code ec;
    fs::rename(path_, resolved_, ec);
    if (ec) throw Error(target_.string() + ": cannot rename the temporary file over it: " + ec.message());
    committed_ = true;
  }

  [[noreturn]] void fail(const std::string& what, int err) const {
    throw Error(target_.string() + ": " + what + ": " + std::strerror(err));
  }

 private:
  fs::path target_;
  fs::path resolved_;  // the file replaced: symlinks written through (core/output_paths.h)
  fs::path path_;
  int fd_ = -1;
  bool committed_ = false;
};

// An output buffer over a file descriptor that keeps the errno of the first failed write.
class FdStreambuf : public std::streambuf {
 public:
  explicit FdStreambuf(int fd) : fd_(fd) { setp(buffer_.data(), buffer_.data() + buffer_.size()); }
  int error() const { return error_; }

 protected:
  int_type overflow(int_type c) override {
    if (!drain()) return traits_type::eof();
    if (!traits_type::eq_int_type(c, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(c);
      pbump(1);
    }
    return traits_type::not_eof(c);
  }
  int sync() override { return drain() ? 0 : -1; }

 private:
  bool drain() {
    for (const char* p = pbase(); p < pptr();) {
      const ssize_t n = ::write(fd_, p, static_cast<size_t>(pptr() - p));
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) {
        error_ = errno;
        return false;
      }
      p += n;
    }
    setp(buffer_.data(), buffer_.data() + buffer_.size());
    return true;
  }

  int fd_;
  int error_ = 0;
  std::array<char, 1 << 16> buffer_;
};

// Runs `write`, turning foreign exceptions into sylva::Error("path: what").
template <typename Write>
void run_writer(const fs::path& path, const Write& write) {
  try {
    write();
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error(path.string() + ": " + e.what());
  }
}

}  // namespace

void write_file_atomic(const fs::path& path, const std::function<void(std::ostream& out)>& write) {
  Temporary tmp(path);
  FdStreambuf buffer(tmp.fd());
  std::ostream out(&buffer);
  run_writer(path, [&] { write(out); });
  out.flush();
  if (!out) tmp.fail("cannot write", buffer.error() != 0 ? buffer.error() : EIO);
  tmp.commit();
}

void write_file_atomic_by_name(const fs::path& path, const std::function<void(const fs::path& temp)>& write) {
  Temporary tmp(path);
  tmp.close();
  run_writer(path, [&] { write(tmp.path()); });
  tmp.commit();
}

}  // namespace sylva
