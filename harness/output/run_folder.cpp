#include "harness/output/run_folder.h"

#include <unistd.h>

#include <fstream>
#include <stdexcept>
#include <system_error>

namespace hb {

namespace fs = std::filesystem;

StagedRunFolder::StagedRunFolder(fs::path destination) : destination_(std::move(destination)) {
  staging_ = destination_;
  staging_ += ".partial-" + std::to_string(::getpid());
  std::error_code ignored;
  fs::remove_all(staging_, ignored);
  fs::create_directories(staging_);
}

StagedRunFolder::~StagedRunFolder() {
  if (!committed_) {
    std::error_code ignored;
    fs::remove_all(staging_, ignored);
  }
}

void StagedRunFolder::write_file(const std::string& name, const std::string& content) const {
  const fs::path path = staging_ / name;
  std::ofstream out(path, std::ios::binary);
  out << content;
  out.close();
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

void StagedRunFolder::commit() {
  // The old folder is moved aside first, so the destination is always
  // either the complete old run or the complete new one.
  fs::path old = destination_;
  old += ".old-" + std::to_string(::getpid());
  const bool had_old = fs::exists(destination_);
  if (had_old) fs::rename(destination_, old);
  fs::rename(staging_, destination_);
  committed_ = true;
  if (had_old) fs::remove_all(old);
}

}  // namespace hb
