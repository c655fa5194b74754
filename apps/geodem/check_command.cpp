#include "check_command.hpp"

#include <algorithm>
#include <cstdio>

#include "io/scenario_check.hpp"
#include "kinds/scenario_kind.hpp"

int check_scenario(geodem::LoadedScenario& l, const std::string& file, int threads) {
  std::string ok;
  const auto found = geodem::find_scenario_problems(l.root, [&](const toml::table& root) {
    ok = geodem::find_kind(l, file).check(root, file, threads, true);
  });
  if (found.errors.empty()) {
    std::printf("%s: ok (%s)\n", file.c_str(), ok.c_str());
    return 0;
  }
  for (const auto& e : found.errors) std::fprintf(stderr, "error: %s\n", e.what());
  const std::size_t n = found.errors.size();
  std::fprintf(stderr, "%s: %zu problem%s%s\n", file.c_str(), n, n == 1 ? "" : "s",
               found.complete ? ""
                              : " (the check stopped at one it cannot read past: fix it and "
                                "check again for those after it)");
  return 2;
}

void check_run_memory(const geodem::LoadedScenario& l, const std::string& file, int threads) {
  (void)geodem::find_kind(l, file).check(l.root, file, threads, false);
}
