// Output files: written so that a crash never leaves one half-written.
// Whole files (JSON, VTK, .pvd) go to a temporary name and are renamed into place;
// the history CSV is appended line by line and flushed after each row.
#pragma once

#include <fstream>
#include <functional>
#include <string>
#include <vector>

namespace geodem {

// Writes `content` to `path` atomically (temporary file + rename).
void write_file_atomic(const std::string& path, const std::string& content);
// The same, with the content streamed by `emit` (a large table need not be held in memory).
void write_file_atomic(const std::string& path, const std::function<void(std::ostream&)>& emit);

// fsync of a file or a folder (a folder: the names renamed into it), best effort.
void sync_to_disk(const std::string& path, bool folder);

// The whole content of a file (runtime_error when it cannot be read).
std::string read_text_file(const std::string& path);

// history.csv: header row first, one row per recorded step.
class HistoryCsv {
 public:
  HistoryCsv() = default;
  void open(const std::string& path, const std::vector<std::string>& columns);
  // Reopens a history written by an interrupted run, kept up to and including `last_step`
  // (its first column): later rows and a last row cut short are dropped, so that the
  // resumed run appends exactly the rows an uninterrupted run would have written.
  void resume(const std::string& path, const std::vector<std::string>& columns, double last_step);
  // The same for a file whose first column is not the step: keeps its first `rows` rows.
  void resume_rows(const std::string& path, const std::vector<std::string>& columns,
                   std::size_t rows);
  void row(const std::vector<double>& values);
  // Every row written so far on disk (flushed and fsynced): before a checkpoint that
  // counts them is put in place.
  void sync();
  bool is_open() const { return out_.is_open(); }
  std::size_t rows() const { return rows_; }

 private:
  // Keeps the whole rows for which keep(row text, row index) holds, up to the first that
  // fails; returns how many.
  template <class Keep>
  std::size_t reopen(const std::string& path, const std::vector<std::string>& columns, Keep keep);
  std::ofstream out_;
  std::string path_;
  std::size_t columns_ = 0, rows_ = 0;
};

// Formats a double the same way everywhere (shortest round-trip form).
std::string format_number(double v);

}  // namespace geodem
