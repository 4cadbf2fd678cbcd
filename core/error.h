#pragma once
// Errors. Every user-facing failure is a sylva::Error whose message is complete as printed; parse
// errors carry `file:line: what was expected` (line 0 when the position is unknown).

#include <filesystem>
#include <stdexcept>
#include <string>

namespace sylva {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class ParseError : public Error {
 public:
  // A place with no line (a command-line override): "file: what".
  static constexpr int kNoLine = -1;
  ParseError(const std::filesystem::path& file, int line, const std::string& what)
      : Error(message(file, line, what)), file_(file), line_(line) {}
  const std::filesystem::path& file() const { return file_; }
  int line() const { return line_; }

 private:
  static std::string message(const std::filesystem::path& file, int line, const std::string& what) {
    std::string m = file.string();
    if (line != kNoLine) m.append(":").append(std::to_string(line));
    m.append(": ").append(what);
    return m;
  }
  std::filesystem::path file_;
  int line_ = 0;
};

}  // namespace sylva
