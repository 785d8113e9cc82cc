#include "hapticbench/disk_cache.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <system_error>

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
std::string payload_checksum(std::string_view bytes) {
  constexpr uint64_t kOdd = 0x9e3779b97f4a7c15ULL;
  const auto step = [](uint64_t lane, uint64_t word) {
    lane = (lane ^ word) * kOdd;
    return lane ^ (lane >> 29);
  };
  uint64_t lanes[4] = {1, 2, 3, 4};
  std::size_t i = 0;
  for (; i + 32 <= bytes.size(); i += 32)
    for (int k = 0; k < 4; ++k) {
      uint64_t word;
      std::memcpy(&word, bytes.data() + i + 8 * k, 8);
      lanes[k] = step(lanes[k], word);
    }
  uint64_t sum = step(bytes.size(), 0);
  for (const uint64_t lane : lanes) sum = step(sum, lane);
  for (; i < bytes.size(); ++i) sum = step(sum, static_cast<unsigned char>(bytes[i]));
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(sum));
  return text;
}

fs::path temporary_sibling(const fs::path& target) {
  static std::atomic<unsigned> counter{0};
  return target.parent_path() / (target.filename().string() + ".tmp-" + std::to_string(::getpid()) +
                                 "-" + std::to_string(counter++));
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

DiskCache::Lookup DiskCache::read(const std::string& key) const {
  Lookup lookup;
  if (!folder_) return lookup;
  const fs::path path = path_of(key);
  std::error_code error;
  if (!fs::exists(path, error)) return lookup;
  const auto fail = [&](const std::string& why) {
    lookup.problem = "cache file " + path.string() + " " + why + "; rebuilt";
    lookup.mapping.reset();
    return lookup;
  };
  // Mapped, not read: a hit costs no copy of what may be tens of megabytes.
  // O_NONBLOCK: a FIFO put in a cache file's place opens at once (and is
  // then refused) instead of blocking until someone writes to it.
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) return fail("is unreadable");
  struct stat status {};
  if (::fstat(fd, &status) != 0 || !S_ISREG(status.st_mode) || status.st_size <= 0) {
    ::close(fd);
    return fail("is not a readable regular file, or is empty");
  }
  const auto file_bytes = static_cast<std::size_t>(status.st_size);
  // The header is read and checked before anything is mapped: a large file
  // of anything else in a cache file's place is never paged in.
  char head[256];
  const ssize_t head_bytes = ::pread(fd, head, sizeof head, 0);
  const CacheHeader header = parse_header(
      std::string_view(head, head_bytes > 0 ? static_cast<std::size_t>(head_bytes) : 0), kind_,
      file_bytes);
  if (!header.problem.empty()) {
    ::close(fd);
    return fail(header.problem);
  }
  void* address = ::mmap(nullptr, file_bytes, PROT_READ, MAP_PRIVATE | MAP_POPULATE, fd, 0);
  ::close(fd);
  if (address == MAP_FAILED) return fail("cannot be mapped");
  lookup.mapping = std::shared_ptr<const void>(
      address, [file_bytes](const void* p) { ::munmap(const_cast<void*>(p), file_bytes); });
  const std::string_view bytes(static_cast<const char*>(address), file_bytes);

  if (bytes.substr(header.header_bytes, header.key_bytes) != key) return fail("holds another key");
  const std::string_view payload =
      bytes.substr(header.header_bytes + header.key_bytes, header.payload_bytes);
  if (payload_checksum(payload) != header.checksum) return fail("is damaged");
  lookup.payload = payload;
  return lookup;
}

std::string DiskCache::write(const std::string& key, std::string_view payload) const {
  if (!folder_) return "";
  const fs::path path = path_of(key);
  const fs::path temporary = temporary_sibling(path);
  std::error_code error;
  fs::create_directories(path.parent_path(), error);
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out << kMagic << kind_ << '\n'
        << key.size() << ' ' << payload.size() << ' ' << payload_checksum(payload) << '\n'
        << key;
    out.write(payload.data(), static_cast<std::streamsize>(payload.size()));
    out.close();
    if (!out) {
      fs::remove(temporary, error);
      return "cache file " + path.string() + " not written (write failed)";
    }
  }
  fs::rename(temporary, path, error);
  if (error) {
    const std::string why = error.message();
    fs::remove(temporary, error);
    return "cache file " + path.string() + " not written (" + why + ")";
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
