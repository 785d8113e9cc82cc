#include "harness/output/output_ownership.h"

#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>

#include "hapticbench/input_error.h"
#include "harness/process/liveness_lock.h"

namespace hb {

namespace fs = std::filesystem;

namespace {

constexpr const char* kWrittenBy = "hapticbench";
// A marker is a few hundred bytes; anything larger is not one of ours.
constexpr std::streamsize kMarkerMaxBytes = 1 << 20;

/// "a symlink", "a regular file", ... for messages about what is in the way.
std::string kind_of(fs::file_type type) {
  switch (type) {
    case fs::file_type::symlink:
      return "a symlink";
    case fs::file_type::regular:
      return "a regular file";
    case fs::file_type::directory:
      return "a folder";
    case fs::file_type::block:
    case fs::file_type::character:
      return "a device";
    case fs::file_type::fifo:
      return "a FIFO";
    case fs::file_type::socket:
      return "a socket";
    default:
      return "something hapticbench cannot identify";
  }
}

struct Marker {
  std::string kind;
  std::set<std::string> files;
};

/// The marker in `folder`; nullopt when there is no readable marker of ours.
std::optional<Marker> read_marker(const fs::path& folder) {
  const fs::path marker_path = folder / kOwnershipMarkerName;
  std::error_code error;
  if (fs::symlink_status(marker_path, error).type() != fs::file_type::regular) return std::nullopt;
  std::ifstream in(marker_path, std::ios::binary);
  std::string text;
  text.resize(kMarkerMaxBytes + 1);
  in.read(text.data(), kMarkerMaxBytes + 1);
  if (in.gcount() > kMarkerMaxBytes) return std::nullopt;
  text.resize(static_cast<std::size_t>(in.gcount()));
  const nlohmann::json json = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (!json.is_object() || json.value("written_by", "") != kWrittenBy || !json.contains("files") ||
      !json["files"].is_array() || !json.contains("kind") || !json["kind"].is_string())
    return std::nullopt;
  Marker marker;
  marker.kind = json["kind"].get<std::string>();
  for (const nlohmann::json& file : json["files"]) {
    if (!file.is_string()) return std::nullopt;
    marker.files.insert(file.get<std::string>());
  }
  return marker;
}

fs::file_type type_at(const fs::path& path) {
  std::error_code error;
  const fs::file_status status = fs::symlink_status(path, error);
  if (error && error != std::errc::no_such_file_or_directory)
    throw InputError(path.string(), "", "cannot inspect the output path: " + error.message());
  return status.type();
}

}  // namespace

const char* output_folder_kind_name(OutputFolderKind kind) {
  return kind == OutputFolderKind::kRun ? "run folder" : "comparison folder";
}

std::string ownership_marker_text(OutputFolderKind kind, const std::vector<std::string>& files) {
  nlohmann::ordered_json marker;
  marker["written_by"] = kWrittenBy;
  marker["kind"] = output_folder_kind_name(kind);
  marker["note"] =
      "hapticbench replaces this folder on a later run only while it holds nothing but these "
      "files";
  marker["files"] = files;
  return marker.dump(2) + "\n";
}

bool is_owned_folder(const fs::path& folder, std::optional<OutputFolderKind> kind) {
  if (type_at(folder) != fs::file_type::directory) return false;
  const std::optional<Marker> marker = read_marker(folder);
  if (!marker || (kind && marker->kind != output_folder_kind_name(*kind))) return false;
  std::error_code error;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder, error)) {
    const std::string name = entry.path().filename().string();
    // The lock a live writer holds (liveness_lock.h) is part of the folder.
    if (name == kOwnershipMarkerName || name == kLivenessLockName) continue;
    if (!marker->files.count(name) || type_at(entry.path()) != fs::file_type::regular) return false;
  }
  return !error;
}

namespace {
constexpr std::size_t kMaxOutputNameBytes = 255 - std::char_traits<char>::length(".partial-") - 10;
}  // namespace

bool require_replaceable_folder(const fs::path& destination, OutputFolderKind kind) {
  if (destination.empty()) throw InputError("", "", "the output path is empty");
  // The folder is staged as <name>.partial-<pid> and set aside as
  // <name>.old-<pid>: those names must fit a file name too (255 bytes), or
  // the run would fail only when it writes, after all its work.
  const std::size_t name_bytes = destination.filename().string().size();
  if (name_bytes > kMaxOutputNameBytes)
    throw InputError(destination.string(), "",
                     "the folder name is " + std::to_string(name_bytes) + " bytes; at most " +
                         std::to_string(kMaxOutputNameBytes) +
                         " (255 less the staging suffix \".partial-<pid>\")");
  const fs::file_type type = type_at(destination);
  if (type == fs::file_type::not_found) return false;
  if (type != fs::file_type::directory)
    throw InputError(destination.string(), "",
                     "is " + kind_of(type) +
                         ", not a folder hapticbench wrote; hapticbench never replaces it "
                         "(choose another output path or remove it yourself)");
  std::error_code error;
  if (fs::is_empty(destination, error) && !error) return false;
  if (is_owned_folder(destination, kind)) return true;
  const std::optional<Marker> marker = read_marker(destination);
  std::string why =
      "is a folder hapticbench did not write (no " + std::string(kOwnershipMarkerName) + " marker)";
  if (marker && marker->kind != output_folder_kind_name(kind))
    why = "is a " + marker->kind + ", not a " + output_folder_kind_name(kind);
  else if (marker)
    why = "holds files hapticbench did not write there";
  throw InputError(destination.string(), "",
                   why +
                       "; hapticbench never replaces it (choose another output path, or an "
                       "empty or new folder)");
}

void require_replaceable_file(const fs::path& destination, const std::string& what,
                              const std::function<bool(const fs::path&)>& written_by_hapticbench) {
  if (destination.empty()) throw InputError("", "", "the output path is empty");
  const fs::file_type type = type_at(destination);
  if (type == fs::file_type::not_found) return;
  if (type != fs::file_type::regular)
    throw InputError(destination.string(), "",
                     "is " + kind_of(type) + ", not a " + what +
                         " hapticbench wrote; hapticbench never replaces it (choose another "
                         "output path)");
  if (!written_by_hapticbench(destination))
    throw InputError(destination.string(), "",
                     "exists and is not a " + what +
                         " hapticbench wrote; hapticbench never replaces it (choose another "
                         "output path or remove it yourself)");
}

void create_output_container(const fs::path& folder) {
  if (folder.empty()) throw InputError("", "", "the output path is empty");
  std::error_code error;
  const fs::file_status status = fs::status(folder, error);
  if (status.type() == fs::file_type::directory) return;
  if (status.type() != fs::file_type::not_found && !error)
    throw InputError(folder.string(), "",
                     "is " + kind_of(status.type()) + ", expected a folder to write into");
  error.clear();
  fs::create_directories(folder, error);
  if (error)
    throw InputError(folder.string(), "", "cannot create the output folder: " + error.message());
}

}  // namespace hb
