#include "hapticbench/disk_cache.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <system_error>

#include "algorithms/core/file_trust.h"
#include "algorithms/core/replacing_file.h"
#include "hapticbench/content_hash.h"

namespace hb {

namespace fs = std::filesystem;

namespace {

constexpr std::string_view kMagic = "hapticbench-cache 3 ";
constexpr std::size_t kMaxKeyBytes = 1 << 20;

// Checksum of a payload (hex): four independent lanes over 8-byte words, so
// that tens of megabytes are checked in a few milliseconds (a byte-wise
// FNV-1a took about 40 ms on the sensation-preserving hierarchies). Each
// step is a bijection of the lane for a fixed word, and the lanes are folded
// the same way, so any change confined to one word always changes the sum.
// Taken in parts of any size, so that a payload never has to be whole in
// memory.
class PayloadChecksum {
 public:
  void add(std::string_view bytes) {
    total_ += bytes.size();
    while (!bytes.empty()) {
      if (pending_ == 0 && bytes.size() >= 32) {
        const std::size_t whole = bytes.size() / 32 * 32;
        for (std::size_t i = 0; i < whole; i += 32) add_block(bytes.data() + i);
        bytes.remove_prefix(whole);
        continue;
      }
      const std::size_t take = std::min<std::size_t>(32 - pending_, bytes.size());
      std::memcpy(block_ + pending_, bytes.data(), take);
      pending_ += take;
      bytes.remove_prefix(take);
      if (pending_ == 32) {
        add_block(block_);
        pending_ = 0;
      }
    }
  }
  std::string hex() const {
    uint64_t sum = step(total_, 0);
    for (const uint64_t lane : lanes_) sum = step(sum, lane);
    for (std::size_t i = 0; i < pending_; ++i)
      sum = step(sum, static_cast<unsigned char>(block_[i]));
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(sum));
    return text;
  }

 private:
  static uint64_t step(uint64_t lane, uint64_t word) {
    constexpr uint64_t kOdd = 0x9e3779b97f4a7c15ULL;
    lane = (lane ^ word) * kOdd;
    return lane ^ (lane >> 29);
  }
  void add_block(const char* block) {
    for (int k = 0; k < 4; ++k) {
      uint64_t word;
      std::memcpy(&word, block + 8 * k, 8);
      lanes_[k] = step(lanes_[k], word);
    }
  }
  uint64_t lanes_[4] = {1, 2, 3, 4};
  uint64_t total_ = 0;
  char block_[32] = {};
  std::size_t pending_ = 0;
};

std::string payload_checksum(std::string_view bytes) {
  PayloadChecksum sum;
  sum.add(bytes);
  return sum.hex();
}

// A cache file's header: "<magic><kind>\n<key bytes> <payload bytes> <checksum>\n".
struct CacheHeader {
  std::size_t header_bytes = 0, key_bytes = 0, payload_bytes = 0;
  std::string checksum;
  std::string problem;  ///< "" when it names this kind and the file's length
};

// Reads the header from the first bytes of a file of `file_bytes` bytes.
CacheHeader parse_header(std::string_view head, const std::string& kind, std::size_t file_bytes) {
  CacheHeader header;
  const std::size_t magic_end = head.find('\n');
  const std::size_t sizes_end =
      magic_end == std::string_view::npos ? magic_end : head.find('\n', magic_end + 1);
  if (magic_end == std::string_view::npos ||
      head.substr(0, magic_end) != std::string(kMagic) + kind ||
      sizes_end == std::string_view::npos || sizes_end - magic_end > 100) {
    header.problem = "has no valid header";
    return header;
  }
  std::istringstream sizes(std::string(head.substr(magic_end + 1, sizes_end - magic_end - 1)));
  if (!(sizes >> header.key_bytes >> header.payload_bytes >> header.checksum)) {
    header.problem = "has no valid header";
    return header;
  }
  header.header_bytes = sizes_end + 1;
  if (header.key_bytes > kMaxKeyBytes || header.payload_bytes > file_bytes ||
      header.header_bytes + header.key_bytes + header.payload_bytes != file_bytes)
    header.problem = "has the wrong length";
  return header;
}

}  // namespace

DiskCache::DiskCache(std::optional<fs::path> folder, std::string kind)
    : folder_(std::move(folder)), kind_(std::move(kind)) {}

fs::path DiskCache::path_of(const std::string& key) const {
  if (!folder_) return {};
  return *folder_ / (kind_ + "-" + ContentHash().add(key).hex() + ".hbcache");
}

// A cache file opened for reading, its header and key checked; closed when
// destroyed. `problem` says why it is not used ("" when it is).
struct DiskCache::OpenedFile {
  int fd = -1;
  std::size_t file_bytes = 0, payload_offset = 0, payload_bytes = 0;
  std::string checksum;
  std::string problem;
  OpenedFile() = default;
  OpenedFile(const OpenedFile&) = delete;
  OpenedFile& operator=(const OpenedFile&) = delete;
  ~OpenedFile() {
    if (fd >= 0) ::close(fd);
  }
};

bool DiskCache::open_checked(const std::string& key, OpenedFile& file) const {
  const fs::path path = path_of(key);
  std::error_code error;
  if (!fs::exists(path, error)) return false;  // a plain miss
  const auto fail = [&](const std::string& why) {
    file.problem = "cache file " + path.string() + " " + why + "; rebuilt";
    return false;
  };
  const std::string folder_problem = writable_by_others(path.parent_path());
  if (!folder_problem.empty())
    return fail("is in a folder other users can change (" + folder_problem +
                "); set HAPTICBENCH_CACHE_DIR to a folder of yours");
  // O_NONBLOCK: a FIFO put in a cache file's place opens at once (and is
  // then refused) instead of blocking until someone writes to it.
  file.fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOFOLLOW);
  if (file.fd < 0) return fail("is unreadable, or a symlink");
  struct stat status {};
  if (::fstat(file.fd, &status) != 0 || !S_ISREG(status.st_mode) || status.st_size <= 0)
    return fail("is not a readable regular file, or is empty");
  // Only what this user (or root) wrote, and nobody else can change, is
  // trusted: a checksum anyone can recompute proves nothing about who wrote
  // the bytes.
  if (status.st_uid != ::geteuid() && status.st_uid != 0)
    return fail("was written by user " + std::to_string(status.st_uid) +
                ", not by this user, and is not trusted");
  if ((status.st_mode & S_IWOTH) || ((status.st_mode & S_IWGRP) && status.st_gid != ::getegid()))
    return fail("is writable by other users and is not trusted");
  file.file_bytes = static_cast<std::size_t>(status.st_size);
  // The header and key are read and checked before any payload: a large
  // file of anything else in a cache file's place is never paged in.
  char head[256];
  const ssize_t head_bytes = ::pread(file.fd, head, sizeof head, 0);
  const CacheHeader header = parse_header(
      std::string_view(head, head_bytes > 0 ? static_cast<std::size_t>(head_bytes) : 0), kind_,
      file.file_bytes);
  if (!header.problem.empty()) return fail(header.problem);
  std::string stored_key(header.key_bytes, '\0');
  if (header.key_bytes != key.size() ||
      ::pread(file.fd, stored_key.data(), stored_key.size(),
              static_cast<off_t>(header.header_bytes)) != static_cast<ssize_t>(key.size()) ||
      stored_key != key)
    return fail("holds another key");
  file.payload_offset = header.header_bytes + header.key_bytes;
  file.payload_bytes = header.payload_bytes;
  file.checksum = header.checksum;
  return true;
}

DiskCache::Lookup DiskCache::read(const std::string& key) const {
  Lookup lookup;
  if (!folder_) return lookup;
  OpenedFile file;
  if (!open_checked(key, file)) {
    lookup.problem = file.problem;
    return lookup;
  }
  // Mapped, not read: a hit costs no copy of what may be tens of megabytes.
  void* address =
      ::mmap(nullptr, file.file_bytes, PROT_READ, MAP_PRIVATE | MAP_POPULATE, file.fd, 0);
  if (address == MAP_FAILED) {
    lookup.problem = "cache file " + path_of(key).string() + " cannot be mapped; rebuilt";
    return lookup;
  }
  const std::size_t file_bytes = file.file_bytes;
  lookup.mapping = std::shared_ptr<const void>(
      address, [file_bytes](const void* p) { ::munmap(const_cast<void*>(p), file_bytes); });
  const std::string_view payload = std::string_view(static_cast<const char*>(address), file_bytes)
                                       .substr(file.payload_offset, file.payload_bytes);
  if (payload_checksum(payload) != file.checksum) {
    lookup.mapping.reset();
    lookup.problem = "cache file " + path_of(key).string() + " is damaged; rebuilt";
    return lookup;
  }
  lookup.payload = payload;
  return lookup;
}

bool DiskCache::read_parts(const std::string& key,
                           const std::function<void(std::string_view)>& consume,
                           std::string* problem) const {
  if (!folder_) return false;
  OpenedFile file;
  if (!open_checked(key, file)) {
    if (problem != nullptr) *problem = file.problem;
    return false;
  }
  PayloadChecksum sum;
  std::string part(std::min<std::size_t>(kPartBytes, file.payload_bytes), '\0');
  for (std::size_t done = 0; done < file.payload_bytes;) {
    const std::size_t want = std::min(part.size(), file.payload_bytes - done);
    const ssize_t got =
        ::pread(file.fd, part.data(), want, static_cast<off_t>(file.payload_offset + done));
    if (got <= 0) {
      if (got < 0 && errno == EINTR) continue;
      if (problem != nullptr)
        *problem = "cache file " + path_of(key).string() + " cannot be read; rebuilt";
      return false;
    }
    const std::string_view bytes(part.data(), static_cast<std::size_t>(got));
    sum.add(bytes);
    consume(bytes);
    done += static_cast<std::size_t>(got);
  }
  if (sum.hex() != file.checksum) {
    if (problem != nullptr)
      *problem = "cache file " + path_of(key).string() + " is damaged; rebuilt";
    return false;
  }
  return true;
}

std::string DiskCache::write(const std::string& key, std::string_view payload) const {
  return write_parts(key, payload.size(),
                     [&](const std::function<void(std::string_view)>& put) { put(payload); });
}

std::string DiskCache::write_parts(const std::string& key, std::uint64_t payload_bytes,
                                   const PartsProducer& produce) const {
  if (!folder_) return "";
  const fs::path path = path_of(key);
  std::error_code error;
  fs::create_directories(path.parent_path(), error);
  PayloadChecksum sum;
  std::uint64_t produced = 0;
  produce([&](std::string_view part) {
    sum.add(part);
    produced += part.size();
  });
  if (produced != payload_bytes)
    return "cache file " + path.string() + " not written (the payload changed size)";
  // Created exclusively beside the file (mkstemp): a name planted in a
  // shared cache folder, a symlink included, is never written through.
  try {
    TemporarySibling file(path);
    std::ostringstream header;
    header << kMagic << kind_ << '\n'
           << key.size() << ' ' << payload_bytes << ' ' << sum.hex() << '\n';
    file.write(header.str());
    file.write(key);
    produce([&](std::string_view part) { file.write(part); });
    file.commit();
  } catch (const fs::filesystem_error& failure) {
    return "cache file " + path.string() + " not written (" + failure.code().message() + ")";
  }
  return "";
}

std::string exact_key_text(const Pose& pose) {
  std::string text;
  for (double v :
       {pose.p.x(), pose.p.y(), pose.p.z(), pose.q.w(), pose.q.x(), pose.q.y(), pose.q.z()})
    text += exact_key_text(v) + " ";
  return text;
}

}  // namespace hb
