// A deposited soil kept on disk for later runs of the same soil (`[soil] deposit_cache`).
//
// Layered deposition is the costly part of preparing a pull-out or an interface shear
// test, and runs that differ only in what comes after it (another anchor, sheet, pull
// rate or estimate) deposit exactly the same soil. The state at the end of the deposit is
// stored as a checkpoint file named after a digest of every setting the deposit depends
// on; a later run with the same settings loads it and goes on bit for bit as if it had
// deposited the soil itself. Settings read only after the deposit are left out of the key
// by the runner; any other setting, the program version and the stage are in it, so a
// changed setting finds no file rather than a wrong one.
#pragma once

#include <initializer_list>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "io/checkpoint.hpp"
#include "io/output_files.hpp"
#include "world/world.hpp"
#include "world/world_state.hpp"

namespace geodem {

class DepositCache {
 public:
  // `folder` empty: no cache. `stage` names the deposit ("pullout_foundation"...);
  // `resolved` is the run's resolved settings; the keys in `after_deposit` (top-level
  // tables or keys, or "table.key") and soil.deposit_cache are not part of the key.
  DepositCache(std::string folder, std::string stage, const nlohmann::json& resolved,
               std::initializer_list<const char*> after_deposit);

  bool enabled() const { return !folder_.empty(); }
  const std::string& path() const { return path_; }
  // The settings the cached deposit depends on (stored in the file and compared on load).
  const std::string& key() const { return key_; }

  // The stored deposit of this key, when a whole file of this key is there; a damaged
  // file or one of other settings (a digest collision) is a miss, reported on stderr.
  std::optional<Checkpoint> load() const;

  // Stores the deposit (atomically: runs side by side may store the same key). A cache
  // that cannot be written is reported on stderr and the run goes on.
  void store(Checkpoint c) const;

  // Stores the world and the runner's own state, visit(StateWriter&); with `csv`, the
  // rows it has written (its file's text) go with them.
  template <int D, class Visit>
  void store(const World<D>& w, Visit&& visit, const std::string& csv_path = {},
             const HistoryCsv* csv = nullptr) const {
    Checkpoint c;
    c.dimension = D, c.step = w.step, c.time = w.time;
    StateWriter runner, world;
    visit(runner);
    if (csv) runner(read_text_file(csv_path)), runner(static_cast<std::uint64_t>(csv->rows()));
    save_world_state(world, w);
    c.runner = std::move(runner.bytes()), c.world = std::move(world.bytes());
    store(std::move(c));
  }

  // Puts a loaded deposit back: the runner's state, visit(StateReader&); the rows of
  // `csv` (rewritten and reopened with `columns`); the world, built as the storing run's
  // was when it stored it.
  template <int D, class Visit>
  static void restore(const Checkpoint& c, World<D>& w, Visit&& visit,
                      const std::string& csv_path = {}, HistoryCsv* csv = nullptr,
                      const std::vector<std::string>& columns = {}) {
    StateReader in(c.runner.data(), c.runner.size());
    visit(in);
    if (csv) {
      std::string text;
      std::uint64_t rows = 0;
      in(text), in(rows);
      write_file_atomic(csv_path, text);
      csv->resume_rows(csv_path, columns, rows);
    }
    StateReader win(c.world.data(), c.world.size());
    load_world_state(win, w);
  }

 private:
  std::string folder_, stage_, key_, path_;
};

}  // namespace geodem
