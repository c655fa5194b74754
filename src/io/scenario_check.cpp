#include "io/scenario_check.hpp"

#include <algorithm>
#include <set>

namespace geodem {

bool remove_dotted_key(toml::table& root, const std::string& dotted) {
  std::vector<std::string> parts;
  std::size_t from = 0;
  for (;;) {
    const auto dot = dotted.find('.', from);
    parts.push_back(dotted.substr(from, dot - from));
    if (dot == std::string::npos) break;
    from = dot + 1;
  }
  toml::node* node = &root;
  for (std::size_t k = 0; k + 1 < parts.size(); ++k) {
    if (auto* t = node->as_table()) {
      node = t->get(parts[k]);
    } else if (auto* a = node->as_array()) {
      const auto& p = parts[k];
      if (p.empty() || p.find_first_not_of("0123456789") != std::string::npos) return false;
      node = a->get(std::stoul(p));
    } else {
      return false;
    }
    if (!node) return false;
  }
  auto* table = node->as_table();
  if (!table || !table->contains(parts.back())) return false;
  // A whole table, or array of tables, is not removed: its own keys are what the reader
  // checks, and without it the reader would report it missing.
  const toml::node* target = table->get(parts.back());
  if (target->is_table() || target->is_array_of_tables()) return false;
  table->erase(parts.back());
  return true;
}

ScenarioProblems find_scenario_problems(toml::table& root,
                                        const std::function<void(const toml::table&)>& read,
                                        int max_problems) {
  ScenarioProblems found;
  std::set<std::string> keys;
  for (int k = 0; k < max_problems; ++k) {
    try {
      read(root);
      break;
    } catch (const InputError& e) {
      // The same key again: the reader misses the value just removed (a required key), a
      // consequence of the search, not the user's problem.
      if (!keys.insert(e.key()).second) {
        found.complete = false;
        break;
      }
      found.errors.push_back(e);
      if (e.key().empty() || !remove_dotted_key(root, e.key())) {
        found.complete = false;
        break;
      }
    }
  }
  std::stable_sort(found.errors.begin(), found.errors.end(),
                   [](const InputError& a, const InputError& b) { return a.line() < b.line(); });
  return found;
}

}  // namespace geodem
