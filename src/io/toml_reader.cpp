#include "io/toml_reader.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

namespace geodem {

namespace {

std::string type_name(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::string:
      return "a string";
    case toml::node_type::integer:
      return "an integer";
    case toml::node_type::floating_point:
      return "a number";
    case toml::node_type::boolean:
      return "a boolean";
    case toml::node_type::array:
      return "an array";
    case toml::node_type::table:
      return "a table";
    default:
      return "a date or time";
  }
}

std::string fmt_num(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

}  // namespace

// Edits between two keys, a swap of neighbouring letters counting as one (the commonest
// typo: 'titel' is one edit from 'title', two from 'time').
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> before(b.size() + 1), prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] != b[j - 1])});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        cur[j] = std::min(cur[j], before[j - 2] + 1);
    }
    std::swap(before, prev);
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

toml::table parse_toml_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "", "cannot open the scenario file");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_toml_text(ss.str(), path);
}

int source_line(const toml::table& root, const std::string& dotted_key) {
  const toml::node* n = &root;
  std::size_t begin = 0;
  while (n && begin <= dotted_key.size()) {
    const std::size_t dot = std::min(dotted_key.find('.', begin), dotted_key.size());
    const std::string part = dotted_key.substr(begin, dot - begin);
    if (const auto* t = n->as_table()) {
      n = t->get(part);
    } else if (const auto* a = n->as_array()) {
      const bool digits =
          !part.empty() && part.find_first_not_of("0123456789") == std::string::npos;
      n = digits && part.size() < 10 ? a->get(std::stoul(part)) : nullptr;
    } else {
      n = nullptr;
    }
    begin = dot + 1;
  }
  return n ? static_cast<int>(n->source().begin.line) : 0;
}

toml::table parse_toml_text(const std::string& text, const std::string& path) {
  if (text.find('\0') != std::string::npos)
    throw InputError(path, 0, "", "the file is binary, not a TOML scenario");
  try {
    return toml::parse(text, path);
  } catch (const toml::parse_error& e) {
    // Quote the line: the parser's words alone ("expected ']'") do not say which key.
    const auto line_no = static_cast<int>(e.source().begin.line);
    std::string line;
    std::size_t at = 0;
    for (int k = 1; k < line_no && at != std::string::npos; ++k) {
      at = text.find('\n', at);
      if (at != std::string::npos) ++at;
    }
    if (at != std::string::npos && line_no > 0) line = text.substr(at, text.find('\n', at) - at);
    if (line.size() > 80) line = line.substr(0, 77) + "...";
    for (char& c : line)
      if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) c = '?';
    std::string msg = std::string("TOML syntax error: ") + std::string(e.description());
    if (!line.empty()) msg += " in: " + line;
    if (std::count(line.begin(), line.end(), '"') % 2 == 1) msg += " (a string is not closed)";
    throw InputError(path, line_no, "", msg);
  }
}

void apply_override(toml::table& root, const std::string& assignment, const std::string& file) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError(file, 0, assignment, "--set expects KEY=VALUE, e.g. --set sample.count=2000");
  const std::string key = assignment.substr(0, eq), value = assignment.substr(eq + 1);
  toml::table parsed_doc;
  try {
    parsed_doc = toml::parse("v = " + value, std::string_view("--set"));
  } catch (const toml::parse_error&) {
    parsed_doc.insert("v", value);  // a bare word is a string
  }
  toml::node& parsed = *parsed_doc.get("v");

  std::vector<std::string> parts;
  std::stringstream ks(key);
  for (std::string p; std::getline(ks, p, '.');) parts.push_back(p);
  toml::node* cur = &root;
  for (std::size_t k = 0; k < parts.size(); ++k) {
    const bool last = k + 1 == parts.size();
    const std::string& p = parts[k];
    if (auto* tb = cur->as_table()) {
      if (last) {
        tb->insert_or_assign(p, std::move(parsed));
        return;
      }
      if (!tb->contains(p)) {
        const bool next_is_index = std::all_of(parts[k + 1].begin(), parts[k + 1].end(), ::isdigit);
        if (next_is_index)
          throw InputError(file, 0, key, "--set: '" + p + "' has no entries to index");
        tb->insert(p, toml::table{});
      }
      cur = tb->get(p);
    } else if (auto* arr = cur->as_array()) {
      if (p.empty() || !std::all_of(p.begin(), p.end(), ::isdigit))
        throw InputError(file, 0, key, "--set: expected an index into the array, got '" + p + "'");
      const std::size_t idx = std::stoul(p);
      if (idx >= arr->size())
        throw InputError(
            file, 0, key,
            "--set: index " + p + " is past the end (size " + std::to_string(arr->size()) + ")");
      if (last) {
        arr->replace(arr->begin() + static_cast<std::ptrdiff_t>(idx), std::move(parsed));
        return;
      }
      cur = arr->get(idx);
    } else {
      throw InputError(file, 0, key, "--set: '" + parts[k - 1] + "' is not a table");
    }
  }
}

TableReader::TableReader(const toml::table& table, std::string path, std::string file,
                         nlohmann::json* out)
    : table_(&table), path_(std::move(path)), file_(std::move(file)), out_(out) {}

const toml::node* TableReader::node(const std::string& key) const {
  used_.insert(key);
  return table_->get(key);
}

std::string TableReader::dotted(const std::string& key) const {
  return path_.empty() ? key : path_ + "." + key;
}

int TableReader::line_of(const std::string& key) const {
  const toml::node* n = table_->get(key);
  const auto& src = n ? n->source() : table_->source();
  return static_cast<int>(src.begin.line);
}

void TableReader::fail(const std::string& key, const std::string& what) const {
  const toml::node* n = table_->get(key);
  std::string file = file_;
  if (n && n->source().path && *n->source().path == "--set") file = file_ + " (--set)";
  throw InputError(file, line_of(key), dotted(key), what);
}

void TableReader::record(const std::string& key, nlohmann::json v) {
  if (out_) (*out_)[key] = std::move(v);
}

bool TableReader::has(const std::string& key) const {
  used_.insert(key);  // a key asked about is a key of this table (for finish()'s suggestions)
  return table_->contains(key);
}

double TableReader::number(const std::string& key) {
  const toml::node* n = node(key);
  if (!n) fail(key, "missing; expected a number");
  std::optional<double> v = n->value<double>();
  if (!n->is_number() || !v) fail(key, "expected a number, got " + type_name(*n));
  if (!std::isfinite(*v)) fail(key, "expected a finite number");
  record(key, *v);
  return *v;
}

double TableReader::number(const std::string& key, double fallback) {
  if (!has(key)) {
    used_.insert(key);
    record(key, fallback);
    return fallback;
  }
  return number(key);
}

double TableReader::positive(const std::string& key, double fallback) {
  const double v = number(key, fallback);
  if (!(v > 0.0)) fail(key, "expected a positive number, got " + fmt_num(v));
  return v;
}

double TableReader::non_negative(const std::string& key, double fallback) {
  const double v = number(key, fallback);
  if (!(v >= 0.0)) fail(key, "expected a number >= 0, got " + fmt_num(v));
  return v;
}

double TableReader::in_range(const std::string& key, double fallback, double lo, double hi) {
  const double v = number(key, fallback);
  if (!(v >= lo && v <= hi))
    fail(key, "expected a number in [" + fmt_num(lo) + ", " + fmt_num(hi) + "], got " + fmt_num(v));
  return v;
}

long long TableReader::integer(const std::string& key, long long fallback, long long lo,
                               long long hi) {
  const toml::node* n = node(key);
  long long v = fallback;
  if (n) {
    if (!n->is_integer()) fail(key, "expected an integer, got " + type_name(*n));
    v = *n->value<long long>();
  }
  if (v < lo || v > hi)
    fail(key, "expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                  "], got " + std::to_string(v));
  record(key, v);
  return v;
}

bool TableReader::boolean(const std::string& key, bool fallback) {
  const toml::node* n = node(key);
  bool v = fallback;
  if (n) {
    if (!n->is_boolean()) fail(key, "expected true or false, got " + type_name(*n));
    v = *n->value<bool>();
  }
  record(key, v);
  return v;
}

std::string TableReader::string(const std::string& key, const std::string& fallback) {
  const toml::node* n = node(key);
  std::string v = fallback;
  if (n) {
    if (!n->is_string()) fail(key, "expected a string, got " + type_name(*n));
    v = *n->value<std::string>();
  }
  record(key, v);
  return v;
}

std::string TableReader::choice(const std::string& key, const std::string& fallback,
                                const std::vector<std::string>& allowed) {
  const std::string v = string(key, fallback);
  if (std::find(allowed.begin(), allowed.end(), v) == allowed.end()) {
    std::string list;
    for (const auto& a : allowed) list += (list.empty() ? "\"" : ", \"") + a + "\"";
    fail(key, "expected one of " + list + ", got \"" + v + "\"");
  }
  return v;
}

std::optional<std::string> TableReader::number_or_string(const std::string& key, double& x,
                                                         const std::string& fallback) {
  const toml::node* n = node(key);
  if (!n) {
    record(key, fallback);
    return fallback;
  }
  if (n->is_string()) {
    record(key, *n->value<std::string>());
    return *n->value<std::string>();
  }
  x = number(key);
  return std::nullopt;
}

std::vector<double> TableReader::numbers(const std::string& key, std::size_t size) {
  const toml::node* n = node(key);
  if (!n) fail(key, "missing; expected an array of " + std::to_string(size) + " numbers");
  std::vector<double> v = numbers(key, {}, size);
  if (v.size() != size)
    fail(key, "expected " + std::to_string(size) + " numbers, got " + std::to_string(v.size()));
  return v;
}

std::vector<double> TableReader::numbers(const std::string& key,
                                         const std::vector<double>& fallback,
                                         std::size_t min_size) {
  const toml::node* n = node(key);
  std::vector<double> v = fallback;
  if (n) {
    const toml::array* arr = n->as_array();
    if (!arr) {
      if (n->is_number()) {
        v = {*n->value<double>()};  // a single value where a list is allowed
      } else {
        fail(key, "expected an array of numbers, got " + type_name(*n));
      }
    } else {
      v.clear();
      for (const auto& e : *arr) {
        if (!e.is_number()) fail(key, "expected an array of numbers, found " + type_name(e));
        const double x = *e.value<double>();
        if (!std::isfinite(x)) fail(key, "expected finite numbers");
        v.push_back(x);
      }
    }
    if (v.size() < min_size)
      fail(key, "expected at least " + std::to_string(min_size) + " numbers, got " +
                    std::to_string(v.size()));
  }
  record(key, v);
  return v;
}

std::vector<std::vector<double>> TableReader::number_rows(const std::string& key,
                                                          std::size_t row_size) {
  const toml::node* n = node(key);
  if (!n || !n->as_array())
    fail(key, "expected an array of points, each of " + std::to_string(row_size) + " numbers");
  std::vector<std::vector<double>> rows;
  for (const auto& e : *n->as_array()) {
    const toml::array* row = e.as_array();
    if (!row || row->size() != row_size)
      fail(key, "expected points of " + std::to_string(row_size) + " numbers");
    std::vector<double> r;
    for (const auto& x : *row) {
      if (!x.is_number()) fail(key, "expected numbers, found " + type_name(x));
      r.push_back(*x.value<double>());
    }
    rows.push_back(r);
  }
  record(key, rows);
  return rows;
}

std::vector<std::string> TableReader::strings(const std::string& key, std::size_t size) {
  const toml::node* n = node(key);
  if (!n || !n->as_array() || n->as_array()->size() != size)
    fail(key, "expected an array of " + std::to_string(size) + " strings");
  std::vector<std::string> v;
  for (const auto& e : *n->as_array()) {
    if (!e.is_string()) fail(key, "expected strings, found " + type_name(e));
    v.push_back(*e.value<std::string>());
  }
  record(key, v);
  return v;
}

std::vector<std::string> TableReader::strings(const std::string& key,
                                              const std::vector<std::string>& fallback) {
  const toml::node* n = node(key);
  if (!n) {
    record(key, fallback);
    return fallback;
  }
  if (!n->as_array()) fail(key, "expected an array of strings, got " + type_name(*n));
  return strings(key, n->as_array()->size());
}

std::optional<TableReader> TableReader::table(const std::string& key) {
  const toml::node* n = node(key);
  if (!n) return std::nullopt;
  if (!n->is_table()) fail(key, "expected a table ([" + dotted(key) + "]), got " + type_name(*n));
  nlohmann::json* sub = nullptr;
  if (out_) {
    (*out_)[key] = nlohmann::json::object();
    sub = &(*out_)[key];
  }
  return TableReader(*n->as_table(), dotted(key), file_, sub);
}

std::vector<TableReader> TableReader::tables(const std::string& key) {
  const toml::node* n = node(key);
  std::vector<TableReader> v;
  if (!n) return v;
  const toml::array* arr = n->as_array();
  if (!arr)
    fail(key, "expected an array of tables ([[" + dotted(key) + "]]), got " + type_name(*n));
  if (out_) (*out_)[key] = nlohmann::json::array();
  for (std::size_t i = 0; i < arr->size(); ++i)
    if (!arr->get(i)->is_table()) fail(key, "expected tables ([[" + dotted(key) + "]])");
  if (out_) (*out_)[key] = std::vector<nlohmann::json>(arr->size(), nlohmann::json::object());
  for (std::size_t i = 0; i < arr->size(); ++i)
    v.emplace_back(*arr->get(i)->as_table(), dotted(key) + "." + std::to_string(i), file_,
                   out_ ? &(*out_)[key][i] : nullptr);
  return v;
}

void TableReader::finish() const {
  for (const auto& [k, n] : *table_) {
    const std::string key(k.str());
    if (used_.count(key)) continue;
    std::string best;
    std::size_t best_d = 4;
    for (const auto& u : used_) {
      const std::size_t d = edit_distance(key, u);
      if (d < best_d) best_d = d, best = u;
    }
    std::string msg = "unknown key";
    if (!best.empty())
      msg += "; did you mean '" + best + "'?";
    else if (!used_.empty()) {
      msg += "; known keys here:";
      for (const auto& u : used_) msg += " " + u;
    }
    throw InputError(file_, static_cast<int>(n.source().begin.line), dotted(key), msg);
  }
}

}  // namespace geodem
