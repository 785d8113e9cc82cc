// Plain values and arrays of them as bytes, for disk-cache payloads
// (disk_cache.h adds key, length and checksum). Values are written as their
// bytes (standard-layout structs of numbers, Eigen's fixed-size vectors
// among them); an array as its length (uint64) then its elements. Readers
// check every length against what is left, so a short or foreign payload
// fails cleanly instead of reading past its end.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace hb {

class PayloadWriter {
 public:
  template <class T>
  void put(const T& value) {
    static_assert(std::is_standard_layout_v<T>);
    bytes_.append(reinterpret_cast<const char*>(&value), sizeof value);
  }
  template <class T>
  void put_array(const std::vector<T>& values) {
    static_assert(std::is_standard_layout_v<T>);
    put(static_cast<uint64_t>(values.size()));
    bytes_.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
  }
  std::string& bytes() { return bytes_; }

 private:
  std::string bytes_;
};

class PayloadReader {
 public:
  explicit PayloadReader(std::string_view bytes) : bytes_(bytes) {}
  template <class T>
  bool get(T& value) {
    static_assert(std::is_standard_layout_v<T>);
    if (remaining() < sizeof value) return false;
    std::memcpy(static_cast<void*>(&value), bytes_.data() + position_, sizeof value);
    position_ += sizeof value;
    return true;
  }
  template <class T>
  bool get_array(std::vector<T>& values) {
    uint64_t count = 0;
    if (!get(count) || count > remaining() / sizeof(T)) return false;
    values.resize(static_cast<std::size_t>(count));
    if (count > 0)
      std::memcpy(static_cast<void*>(values.data()), bytes_.data() + position_,
                  values.size() * sizeof(T));
    position_ += values.size() * sizeof(T);
    return true;
  }
  std::size_t remaining() const { return bytes_.size() - position_; }
  bool at_end() const { return position_ == bytes_.size(); }

 private:
  std::string_view bytes_;
  std::size_t position_ = 0;
};

}  // namespace hb
