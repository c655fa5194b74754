// Fuzz target of the scenario reader: any bytes in, either settings or an InputError out.
// Anything else (another exception, a crash, a sanitizer report, a hang) is a defect.
// Built with libFuzzer by scripts/fuzz.sh (clang); replayed over the kept corpus by the
// test suite (replay_main.cpp, any compiler).
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "base/error.hpp"
#include "kinds/scenario_kind.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const auto scenario = geodem::load_known_scenario_text(text, "fuzz.toml");
    (void)geodem::find_kind(scenario, "fuzz.toml").check(scenario.root, "fuzz.toml", 1, false);
  } catch (const geodem::InputError& e) {
    // Expected for bad input; the message must name the file.
    if (std::string(e.what()).rfind("fuzz.toml", 0) != 0) {
      std::fprintf(stderr, "input error without the file's name: %s\n", e.what());
      std::abort();
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "not an input error: %s\n", e.what());
    std::abort();
  }
  return 0;
}
