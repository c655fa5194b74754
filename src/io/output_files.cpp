#include "io/output_files.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace geodem {

void write_file_atomic(const std::string& path, const std::string& content) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("cannot write " + tmp);
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    out.flush();
    if (!out) throw std::runtime_error("error writing " + tmp);
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
    throw std::runtime_error("cannot rename " + tmp + " to " + path);
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
  columns_ = columns.size();
  for (std::size_t k = 0; k < columns.size(); ++k) out_ << (k ? "," : "") << columns[k];
  out_ << '\n';
  out_.flush();
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
