#include "io/output_files.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <stdexcept>

namespace geodem {

void sync_to_disk(const std::string& path, bool folder) {
  const int fd = ::open(path.c_str(), folder ? (O_RDONLY | O_DIRECTORY) : O_RDONLY);
  if (fd < 0) return;
  (void)::fsync(fd);
  ::close(fd);
}

void write_file_atomic(const std::string& path, const std::string& content) {
  write_file_atomic(path, [&content](std::ostream& out) {
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
  });
}

void write_file_atomic(const std::string& path, const std::function<void(std::ostream&)>& emit) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("cannot write " + tmp);
    emit(out);
    out.flush();
    if (!out) throw std::runtime_error("error writing " + tmp);
  }
  sync_to_disk(tmp, false);  // the content on disk before the name points to it
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
    throw std::runtime_error("cannot rename " + tmp + " to " + path);
}

void HistoryCsv::sync() {
  if (!out_.is_open()) return;
  out_.flush();
  if (!out_) throw std::runtime_error("error writing " + path_ + " (disk full?)");
  sync_to_disk(path_, false);
}

std::string read_text_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

std::string format_number(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[32];
  auto res = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, res.ptr);
}

void HistoryCsv::open(const std::string& path, const std::vector<std::string>& columns) {
  out_.open(path, std::ios::trunc);
  if (!out_) throw std::runtime_error("cannot write " + path);
  path_ = path;
  columns_ = columns.size();
  for (std::size_t k = 0; k < columns.size(); ++k) out_ << (k ? "," : "") << columns[k];
  out_ << '\n';
  out_.flush();
}

template <class Keep>
std::size_t HistoryCsv::reopen(const std::string& path, const std::vector<std::string>& columns,
                               Keep keep) {
  std::string header;
  for (std::size_t k = 0; k < columns.size(); ++k) header += (k ? "," : "") + columns[k];
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot resume: " + path + " is missing");
  std::string line, kept;
  if (!std::getline(in, line) || line != header)
    throw std::runtime_error("cannot resume: " + path + " has another header than this run's");
  kept = header + '\n';
  std::size_t rows = 0;
  // A row is whole when it ends in a newline and has every column.
  while (std::getline(in, line) && !in.eof()) {
    if (static_cast<std::size_t>(std::count(line.begin(), line.end(), ',')) + 1 != columns.size())
      break;
    if (!keep(line, rows)) break;
    kept += line + '\n';
    ++rows;
  }
  in.close();
  write_file_atomic(path, kept);
  if (out_.is_open()) out_.close();
  out_.clear();
  out_.open(path, std::ios::app);
  if (!out_) throw std::runtime_error("cannot write " + path);
  path_ = path;
  columns_ = columns.size();
  rows_ = rows;
  return rows;
}

void HistoryCsv::resume(const std::string& path, const std::vector<std::string>& columns,
                        double last_step) {
  reopen(path, columns, [last_step](const std::string& line, std::size_t) {
    return std::strtod(line.c_str(), nullptr) <= last_step;
  });
}

void HistoryCsv::resume_rows(const std::string& path, const std::vector<std::string>& columns,
                             std::size_t rows) {
  if (reopen(path, columns, [rows](const std::string&, std::size_t i) { return i < rows; }) != rows)
    throw std::runtime_error("cannot resume: " + path + " has fewer rows than the checkpoint's " +
                             std::to_string(rows));
}

void HistoryCsv::row(const std::vector<double>& values) {
  if (values.size() != columns_) throw std::logic_error("history row has the wrong width");
  std::string line;
  for (std::size_t k = 0; k < values.size(); ++k) {
    if (k) line += ',';
    line += format_number(values[k]);
  }
  line += '\n';
  out_ << line;  // one write per row, then flush: a crash leaves whole rows only
  out_.flush();
  ++rows_;
}

}  // namespace geodem
