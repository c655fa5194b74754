#include "lab/deposit_cache.hpp"

#include <zlib.h>

#include <cstdio>
#include <filesystem>
#include <iostream>

#include "io/run_output.hpp"

namespace geodem {

DepositCache::DepositCache(std::string folder, std::string stage, const nlohmann::json& resolved,
                           std::initializer_list<const char*> after_deposit)
    : folder_(std::move(folder)), stage_(std::move(stage)) {
  if (folder_.empty()) return;
  nlohmann::json key = resolved;
  auto erase = [&key](const std::string& dotted) {
    const auto dot = dotted.find('.');
    if (dot == std::string::npos) return void(key.erase(dotted));
    const std::string table = dotted.substr(0, dot);
    if (key.contains(table) && key[table].is_object()) key[table].erase(dotted.substr(dot + 1));
  };
  for (const char* k : after_deposit) erase(k);
  erase("soil.deposit_cache");
  key["deposit_stage"] = stage_;
  key["geodem_version"] = version();
  key_ = key.dump();  // object keys sorted: the same settings give the same text
  // The digest names the file; the key inside it decides.
  const auto crc = crc32_z(0L, reinterpret_cast<const Bytef*>(key_.data()), key_.size());
  char name[32];
  std::snprintf(name, sizeof name, "_%08lx.bin", static_cast<unsigned long>(crc));
  path_ = folder_ + "/" + stage_ + name;
}

std::optional<Checkpoint> DepositCache::load() const {
  if (!enabled() || !std::filesystem::exists(path_)) return std::nullopt;
  try {
    Checkpoint c = read_checkpoint(path_);
    if (c.kind == stage_ && c.scenario == key_) return c;
    std::cerr << "deposit cache: " << path_ << " holds a deposit of other settings; depositing\n";
  } catch (const CheckpointError& e) {
    std::cerr << "deposit cache: " << path_ << " is unusable (" << e.what() << "); depositing\n";
  }
  return std::nullopt;
}

void DepositCache::store(Checkpoint c) const {
  if (!enabled()) return;
  c.kind = stage_;
  c.scenario = key_;
  try {
    std::filesystem::create_directories(folder_);
    write_checkpoint_file(path_, c);
  } catch (const std::exception& e) {
    std::cerr << "deposit cache: cannot store " << path_ << " (" << e.what()
              << "); the run goes on without it\n";
  }
}

}  // namespace geodem
