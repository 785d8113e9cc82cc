// An append-only sequence of a run's per-tick values in constant memory:
// kept in memory while small, then written in blocks to an anonymous
// temporary file, and read back in order.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <type_traits>
#include <vector>

namespace hb {

/// An anonymous file in the temporary folder (TMPDIR), removed when closed
/// or when the process ends. Errors throw std::filesystem::filesystem_error
/// naming the folder (a full disk is the user's to fix).
class SpillFile {
 public:
  SpillFile();
  ~SpillFile();
  SpillFile(const SpillFile&) = delete;
  SpillFile& operator=(const SpillFile&) = delete;
  /// Appends `bytes` bytes.
  void append(const void* data, std::size_t bytes);
  /// Reads `bytes` bytes at `offset` (inside what was appended).
  void read(uint64_t offset, void* data, std::size_t bytes) const;

 private:
  int fd_ = -1;
  uint64_t size_ = 0;
};

/// Values of a trivially copyable type in append order. Memory: at most
/// kBlockBytes (1 MB) plus one block per reader; the rest is on disk.
template <class T>
class SpillBuffer {
  static_assert(std::is_trivially_copyable_v<T>);

 public:
  static constexpr std::size_t kBlockBytes = std::size_t{1} << 20;
  static constexpr std::size_t kBlockItems = kBlockBytes / sizeof(T);

  void push_back(const T& value) {
    if (tail_.size() == kBlockItems) {
      if (!file_) file_ = std::make_unique<SpillFile>();
      file_->append(tail_.data(), tail_.size() * sizeof(T));
      spilled_ += tail_.size();
      tail_.clear();
    }
    if (tail_.capacity() == 0) tail_.reserve(kBlockItems);
    tail_.push_back(value);
  }
  std::size_t size() const { return spilled_ + tail_.size(); }

  /// Reads the values back in order, one block at a time.
  class Reader {
   public:
    explicit Reader(const SpillBuffer& buffer) : buffer_(buffer) {}
    /// The next value into `out`; false at the end.
    bool next(T& out) {
      if (index_ >= buffer_.size()) return false;
      if (index_ >= buffer_.spilled_) {
        out = buffer_.tail_[index_++ - buffer_.spilled_];
        return true;
      }
      if (index_ >= block_begin_ + block_.size()) {
        const std::size_t count = std::min(kBlockItems, buffer_.spilled_ - index_);
        block_.resize(count);
        buffer_.file_->read(static_cast<uint64_t>(index_) * sizeof(T), block_.data(),
                            count * sizeof(T));
        block_begin_ = index_;
      }
      out = block_[index_++ - block_begin_];
      return true;
    }

   private:
    const SpillBuffer& buffer_;
    std::size_t index_ = 0;
    std::size_t block_begin_ = 0;
    std::vector<T> block_;
  };

  template <class Function>
  void for_each(Function&& function) const {
    Reader reader(*this);
    T value;
    while (reader.next(value)) function(value);
  }

 private:
  std::unique_ptr<SpillFile> file_;
  std::size_t spilled_ = 0;  ///< values in the file, before tail_
  std::vector<T> tail_;
};

}  // namespace hb
