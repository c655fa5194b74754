// Error types that map onto the exit codes of the command line (docs/cli.md):
// InputError -> 2, InstabilityError -> 3, anything else -> 1.
#pragma once

#include <sstream>
#include <stdexcept>
#include <string>

namespace geodem {

// Bad input: names the file, the line (0 when unknown), the key and what was expected.
class InputError : public std::runtime_error {
 public:
  InputError(std::string file, int line, std::string key, const std::string& what)
      : std::runtime_error(format(file, line, key, what)),
        file_(std::move(file)),
        line_(line),
        key_(std::move(key)),
        detail_(what) {}
  const std::string& file() const { return file_; }
  int line() const { return line_; }
  const std::string& key() const { return key_; }
  const std::string& detail() const { return detail_; }  // what was expected

 private:
  static std::string format(const std::string& file, int line, const std::string& key,
                            const std::string& what) {
    std::ostringstream s;  // (not operator+: GCC 12 warns falsely on it at -O3)
    s << (file.empty() ? std::string("input") : file);
    if (line > 0) s << ':' << line;
    if (!key.empty()) s << ": key '" << key << "'";
    s << ": " << what;
    return s.str();
  }
  std::string file_;
  int line_;
  std::string key_;
  std::string detail_;
};

// The simulation became unstable: names the step, the body and a likely cause.
class InstabilityError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace geodem
