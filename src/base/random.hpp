// Reproducible random numbers: std::mt19937_64 is fully specified by the standard,
// and the conversion to [0, 1) is done here, so a seed gives the same grains on
// every platform (std::uniform_real_distribution is implementation-defined).
#pragma once

#include <cstdint>
#include <random>
#include <sstream>
#include <string>

namespace geodem {

class Random {
 public:
  explicit Random(std::uint64_t seed) : engine_(seed) {}
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  // The engine's state as the standard's text form (checkpoints), and back.
  std::string state() const {
    std::ostringstream out;
    out << engine_;
    return out.str();
  }
  bool set_state(const std::string& text) {
    std::istringstream in(text);
    in >> engine_;
    return !in.fail();
  }

 private:
  std::mt19937_64 engine_;
};

}  // namespace geodem
