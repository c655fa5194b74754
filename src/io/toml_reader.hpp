// Typed, checked reading of a TOML scenario. Every key read is recorded with its
// value (given or default) so the resolved settings can be written back in
// summary.json; keys left unread are rejected with the closest known key.
#pragma once

#include <toml++/toml.h>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "base/error.hpp"

namespace geodem {

// Parses a TOML file; errors become InputError with file and line.
toml::table parse_toml_file(const std::string& path);
// Line of a dotted key ("shear.confining_stress") in a parsed file, 0 if absent.
int source_line(const toml::table& root, const std::string& dotted_key);

// The same for text in memory; `name` stands for the file in messages.
toml::table parse_toml_text(const std::string& text, const std::string& name);

// Applies `--set dotted.key=value` (value in TOML syntax, or a bare string).
// Numeric path parts index arrays of tables: walls.0.velocity=[0,0,-1].
void apply_override(toml::table& root, const std::string& assignment, const std::string& file);

// Reads one table; `path` is its dotted location for messages.
class TableReader {
 public:
  TableReader(const toml::table& table, std::string path, std::string file, nlohmann::json* out);

  bool has(const std::string& key) const;
  double number(const std::string& key, double fallback);
  double number(const std::string& key);                     // required
  double positive(const std::string& key, double fallback);  // > 0
  double non_negative(const std::string& key, double fallback);
  double in_range(const std::string& key, double fallback, double lo, double hi);
  long long integer(const std::string& key, long long fallback, long long lo, long long hi);
  bool boolean(const std::string& key, bool fallback);
  std::string string(const std::string& key, const std::string& fallback);
  std::string choice(const std::string& key, const std::string& fallback,
                     const std::vector<std::string>& allowed);
  // A number or a string: returns the string if the value is one, else nullopt and sets x.
  std::optional<std::string> number_or_string(const std::string& key, double& x,
                                              const std::string& fallback);
  std::vector<double> numbers(const std::string& key, std::size_t size);  // exact size
  std::vector<double> numbers(const std::string& key, const std::vector<double>& fallback,
                              std::size_t min_size = 0);
  std::vector<std::vector<double>> number_rows(const std::string& key, std::size_t row_size);
  std::vector<std::string> strings(const std::string& key, std::size_t size);  // exact size
  std::vector<std::string> strings(const std::string& key,
                                   const std::vector<std::string>& fallback);

  std::optional<TableReader> table(const std::string& key);
  std::vector<TableReader> tables(const std::string& key);  // array of tables

  // Rejects keys that were never read.
  void finish() const;

  [[noreturn]] void fail(const std::string& key, const std::string& what) const;
  int line_of(const std::string& key) const;
  const std::string& path() const { return path_; }
  const std::string& file() const { return file_; }

 private:
  const toml::node* node(const std::string& key) const;
  std::string dotted(const std::string& key) const;
  void record(const std::string& key, nlohmann::json v);

  const toml::table* table_;
  std::string path_, file_;
  nlohmann::json* out_;
  mutable std::set<std::string> used_;
};

// Edit distance, for "did you mean".
std::size_t edit_distance(const std::string& a, const std::string& b);

}  // namespace geodem
