// Checkpoint files: a run's complete state at the end of a step, in DIR/checkpoint/.
//
// File layout (little-endian machine order): "GEODEMCK", format version (u32), a byte-order
// and type-size mark (u32), payload length (u64), CRC-32 of the payload (u32), payload.
// A file is written under a temporary name, flushed to disk and renamed, so a crash leaves
// either the previous checkpoints or the new one whole; the oldest are pruned only after
// the newest is in place. Loading verifies length and checksum and falls back to the
// previous file when the newest is corrupt or truncated.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "base/state_archive.hpp"

namespace geodem {

// [checkpoint] of a scenario. Off unless a period is given; a signal (io/interrupt.hpp)
// writes one in any case.
struct CheckpointSpec {
  std::uint64_t every_steps = 0;  // 0: off
  double every_seconds = 0.0;     // wall-clock seconds; 0: off
  int keep = 2;                   // newest files kept (older ones are the fallback)
  bool enabled() const { return every_steps > 0 || every_seconds > 0.0; }
};

struct Checkpoint {
  std::string kind;  // scenario kind
  int dimension = 3;
  std::uint64_t step = 0;
  double time = 0.0;
  std::string scenario;  // the resolved settings (JSON) of the run that wrote it
  std::string runner;    // the runner's own state (outputs written so far...), an archive
  std::string world;     // save_world_state()
  std::string path;      // where it was read from (not stored)
};

std::string checkpoint_folder(const std::string& out_dir);

// Writes one checkpoint file at `path` atomically (temporary name of this process, synced,
// renamed): a crash leaves the previous file or the new one whole.
void write_checkpoint_file(const std::string& path, const Checkpoint& c);

// The same, with the world part written by save_world(StateWriter&) straight into the
// file (c.world is ignored): a first pass counts its bytes, a second streams them, so no
// copy of the world is held in memory. The file is byte for byte the one
// write_checkpoint_file would write.
void write_checkpoint_file(const std::string& path, const Checkpoint& c,
                           const std::function<void(StateWriter&)>& save_world);

// Writes the checkpoint atomically into out_dir's checkpoint folder and keeps the `keep` newest
// files; returns its path.
std::string write_checkpoint(const std::string& out_dir, const Checkpoint& c, int keep);
// The same with a streamed world (above).
std::string write_checkpoint(const std::string& out_dir, const Checkpoint& c, int keep,
                             const std::function<void(StateWriter&)>& save_world);

// The newest valid checkpoint of out_dir; each file skipped as invalid is reported in
// `skipped` ("name: reason"). Throws CheckpointError when there is none.
Checkpoint load_latest_checkpoint(const std::string& out_dir, std::vector<std::string>* skipped);

// Deletes the checkpoint files of steps after `step` (a resumed run's abandoned future,
// such as a damaged newest file), so that pruning keeps the resumed run's own files.
void discard_checkpoints_after(const std::string& out_dir, std::uint64_t step);

// Reads and verifies one file (CheckpointError if it is not a whole, valid checkpoint).
Checkpoint read_checkpoint(const std::string& path);

}  // namespace geodem
