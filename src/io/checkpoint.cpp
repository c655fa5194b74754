#include "io/checkpoint.hpp"

#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <thread>

#include "io/output_files.hpp"

namespace geodem {

namespace {

namespace fs = std::filesystem;

constexpr char kMagic[8] = {'G', 'E', 'O', 'D', 'E', 'M', 'C', 'K'};
// 2: 2D tangential springs are scalars; 3: one integral sum per stress servo; 4: the
// periodic cell; 5: a wall's second edge (rectangles); 6: a pull-out's sheet parts (the
// bend's corner and the row sums of the parts' loads); 7: a decomposed run's skin, ghost width
// and clump reach; 9: a decomposed triaxial test's samples; 10: a decomposed pull-out's keys and
// history.
constexpr std::uint32_t kFormatVersion = 10;
// Byte order and the sizes the archive relies on, in one word.
constexpr std::uint32_t kMachineMark =
    0x01020000u | static_cast<std::uint32_t>(sizeof(void*) << 8) | sizeof(double);
constexpr std::size_t kHeaderBytes = 8 + 4 + 4 + 8 + 4;

std::uint32_t crc32_of(const char* p, std::size_t n) {
  return static_cast<std::uint32_t>(
      crc32_z(0L, reinterpret_cast<const Bytef*>(p), static_cast<z_size_t>(n)));
}

// Step of "checkpoint_000000001234.bin", or -1 for any other name.
long long step_of(const std::string& name) {
  const std::string prefix = "checkpoint_", suffix = ".bin";
  if (name.size() != prefix.size() + 12 + suffix.size() || name.rfind(prefix, 0) != 0 ||
      name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
    return -1;
  long long step = 0;
  for (std::size_t k = prefix.size(); k < prefix.size() + 12; ++k) {
    if (name[k] < '0' || name[k] > '9') return -1;
    step = step * 10 + (name[k] - '0');
  }
  return step;
}

// The checkpoint files of a folder, newest first.
std::vector<fs::path> checkpoint_files(const std::string& folder) {
  std::vector<std::pair<long long, fs::path>> found;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(folder, ec)) {
    const long long s = step_of(e.path().filename().string());
    if (s >= 0) found.emplace_back(s, e.path());
  }
  std::sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a > b; });
  std::vector<fs::path> out;
  for (auto& f : found) out.push_back(f.second);
  return out;
}

}  // namespace

std::string checkpoint_folder(const std::string& out_dir) {
  return out_dir + "/checkpoint";
}

void write_checkpoint_file(const std::string& path, const Checkpoint& c,
                           const std::function<void(StateWriter&)>& save_world) {
  // The payload is the archive of (kind, dimension, step, time, scenario, runner, world):
  // the small fields and each string's length prefix, then the runner's bytes as they are,
  // then the world's, streamed into the file (a first pass counts them for the length).
  StateWriter counter([](const char*, std::size_t) {});
  save_world(counter);
  const std::uint64_t world_size = counter.size();
  StateWriter small, runner_len, world_len;
  small(c.kind), small(c.dimension), small(c.step), small(c.time), small(c.scenario);
  runner_len(static_cast<std::uint64_t>(c.runner.size()));
  world_len(world_size);
  const std::string* pieces[] = {&small.bytes(), &runner_len.bytes(), &c.runner,
                                 &world_len.bytes()};
  std::uint64_t length = world_size;
  for (const std::string* piece : pieces) length += piece->size();

  std::string head(kMagic, sizeof kMagic);
  auto put = [&head](const auto& v) { head.append(reinterpret_cast<const char*>(&v), sizeof v); };
  put(kFormatVersion), put(kMachineMark), put(length);
  const auto crc_at = static_cast<std::streamoff>(head.size());
  put(std::uint32_t{0});  // the checksum, written once the payload has gone through

  // A temporary name of this process and thread alone: runs side by side (processes, or a
  // study's runs as threads of one) may write the same file.
  const fs::path target(path);
  const std::string folder = target.parent_path().empty() ? "." : target.parent_path().string();
  const std::string tmp =
      folder + "/." + target.filename().string() + "." + std::to_string(::getpid()) + "." +
      std::to_string(std::hash<std::thread::id>{}(std::this_thread::get_id())) + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("cannot write " + tmp);
    out.write(head.data(), static_cast<std::streamsize>(head.size()));
    uLong crc = crc32_z(0L, Z_NULL, 0);
    auto emit = [&](const char* p, std::size_t n) {
      crc = crc32_z(crc, reinterpret_cast<const Bytef*>(p), static_cast<z_size_t>(n));
      out.write(p, static_cast<std::streamsize>(n));
    };
    for (const std::string* piece : pieces) emit(piece->data(), piece->size());
    StateWriter world(emit);
    save_world(world);
    if (world.size() != world_size)
      throw std::logic_error("a checkpoint's world gave two sizes in its two passes");
    const auto sum = static_cast<std::uint32_t>(crc);
    out.seekp(crc_at);
    out.write(reinterpret_cast<const char*>(&sum), sizeof sum);
    out.flush();
    if (!out) throw std::runtime_error("error writing " + tmp + " (disk full?)");
  }
  sync_to_disk(tmp, false);  // the data on disk before the name points to it
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
    throw std::runtime_error("cannot rename " + tmp + " to " + path);
  sync_to_disk(folder, true);
}

void write_checkpoint_file(const std::string& path, const Checkpoint& c) {
  write_checkpoint_file(path, c, [&c](StateWriter& w) { w.raw(c.world); });
}

std::string write_checkpoint(const std::string& out_dir, const Checkpoint& c, int keep) {
  return write_checkpoint(out_dir, c, keep, [&c](StateWriter& w) { w.raw(c.world); });
}

std::string write_checkpoint(const std::string& out_dir, const Checkpoint& c, int keep,
                             const std::function<void(StateWriter&)>& save_world) {
  const std::string folder = checkpoint_folder(out_dir);
  fs::create_directories(folder);
  char name[64];
  std::snprintf(name, sizeof name, "checkpoint_%012llu.bin",
                static_cast<unsigned long long>(c.step));
  const std::string path = folder + "/" + name;
  write_checkpoint_file(path, c, save_world);

  const auto files = checkpoint_files(folder);
  for (std::size_t k = static_cast<std::size_t>(std::max(keep, 1)); k < files.size(); ++k) {
    std::error_code ec;
    fs::remove(files[k], ec);
  }
  return path;
}

void discard_checkpoints_after(const std::string& out_dir, std::uint64_t step) {
  for (const auto& f : checkpoint_files(checkpoint_folder(out_dir))) {
    if (static_cast<std::uint64_t>(step_of(f.filename().string())) <= step) break;  // newest first
    std::error_code ec;
    fs::remove(f, ec);
  }
}

Checkpoint read_checkpoint(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw CheckpointError("cannot be read");
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.size() < kHeaderBytes) throw CheckpointError("truncated header");
  if (bytes.compare(0, sizeof kMagic, kMagic, sizeof kMagic) != 0)
    throw CheckpointError("not a geodem checkpoint");
  StateReader head(bytes.data() + sizeof kMagic, kHeaderBytes - sizeof kMagic);
  std::uint32_t version = 0, mark = 0, crc = 0;
  std::uint64_t length = 0;
  head(version), head(mark), head(length), head(crc);
  if (version != kFormatVersion)
    throw CheckpointError("format version " + std::to_string(version) + ", this program reads " +
                          std::to_string(kFormatVersion));
  if (mark != kMachineMark) throw CheckpointError("written on a machine of another byte order");
  if (length != bytes.size() - kHeaderBytes)
    throw CheckpointError("truncated: " + std::to_string(bytes.size() - kHeaderBytes) + " of " +
                          std::to_string(length) + " bytes");
  const char* body = bytes.data() + kHeaderBytes;
  if (crc32_of(body, length) != crc) throw CheckpointError("checksum mismatch (corrupt)");
  Checkpoint c;
  StateReader r(body, length);
  r(c.kind), r(c.dimension), r(c.step), r(c.time), r(c.scenario), r(c.runner), r(c.world);
  if (!r.at_end()) throw CheckpointError("trailing bytes");
  c.path = path;
  return c;
}

Checkpoint load_latest_checkpoint(const std::string& out_dir, std::vector<std::string>* skipped) {
  const std::string folder = checkpoint_folder(out_dir);
  std::string reasons;
  for (const auto& f : checkpoint_files(folder)) {
    try {
      return read_checkpoint(f.string());
    } catch (const CheckpointError& e) {
      const std::string why = f.filename().string() + ": " + e.what();
      if (skipped) skipped->push_back(why);
      reasons += (reasons.empty() ? " (" : "; ") + why;
    }
  }
  throw CheckpointError("no valid checkpoint in " + folder +
                        (reasons.empty() ? "" : reasons + ")"));
}

}  // namespace geodem
