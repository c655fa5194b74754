#include "io/memory_budget.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "base/error.hpp"

namespace geodem {

double run_memory_bytes(int dimension, double grains, int runs_at_once) {
  const double per_grain = 1.5 * (dimension == 3 ? 750.0 : 680.0);
  const double base = 10e6;  // the program itself
  return base + static_cast<double>(std::max(runs_at_once, 1)) * per_grain * grains;
}

namespace {
double meminfo_available() {
  std::ifstream in("/proc/meminfo");
  std::string key;
  double kb = 0.0;
  std::string unit;
  while (in >> key >> kb >> unit)
    if (key == "MemAvailable:") return kb * 1024.0;
  return -1.0;
}
double cgroup_limit() {
  std::ifstream in("/sys/fs/cgroup/memory.max");
  std::string v;
  if (!(in >> v) || v == "max") return -1.0;
  return std::strtod(v.c_str(), nullptr);
}
}  // namespace

double available_memory_bytes() {
  if (const char* env = std::getenv("GEODEM_MEMORY_LIMIT")) return std::strtod(env, nullptr);
  double a = meminfo_available();
  const double c = cgroup_limit();
  if (c > 0.0 && (a < 0.0 || c < a)) a = c;
  return a;
}

std::string format_bytes(double b) {
  char buf[32];
  if (b >= 1e9)
    std::snprintf(buf, sizeof buf, "%.3g GB", b / 1e9);
  else
    std::snprintf(buf, sizeof buf, "%.3g MB", b / 1e6);
  return buf;
}

void check_memory(const std::string& file, int line, const std::string& key, int dimension,
                  double grains, int runs_at_once) {
  const double need = run_memory_bytes(dimension, grains, runs_at_once);
  const double have = available_memory_bytes();
  if (have <= 0.0 || need <= have) return;
  char count[32];
  std::snprintf(count, sizeof count, "%.3g", grains);
  throw InputError(
      file, line, key,
      std::string("this run needs about ") + format_bytes(need) + " of memory (" + count +
          " grains" +
          (runs_at_once > 1 ? " per run, " + std::to_string(runs_at_once) + " runs side by side"
                            : std::string()) +
          ", about " +
          std::to_string(
              static_cast<long long>((need - run_memory_bytes(dimension, 0.0)) /
                                     (std::max(grains, 1.0) * std::max(runs_at_once, 1)))) +
          " bytes a grain with its contacts and checkpoint) and the machine has " +
          format_bytes(have) + " available: lower the grain count" +
          (runs_at_once > 1 ? " or --threads" : ""));
}

}  // namespace geodem
