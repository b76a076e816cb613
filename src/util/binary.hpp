// Fixed-width binary fields in host byte order (little-endian on every supported
// platform), for the saved forms of accumulators and run states.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>

#include "slidespec/input_error.hpp"

namespace slidespec::util {

template <class T>
void put(std::string& bytes, T value) {
  char raw[sizeof(T)];
  std::memcpy(raw, &value, sizeof(T));
  bytes.append(raw, sizeof(T));
}

/// A length-prefixed byte string.
inline void put_bytes(std::string& bytes, const std::string& value) {
  put<std::uint64_t>(bytes, value.size());
  bytes += value;
}

/// Reads what put() wrote; a short read throws InputError naming `what` and the offset.
class Reader {
 public:
  Reader(const std::string& bytes, std::string what) : bytes_(bytes), what_(std::move(what)) {}
  template <class T>
  T get() {
    need(sizeof(T));
    T value;
    std::memcpy(&value, bytes_.data() + position_, sizeof(T));
    position_ += sizeof(T);
    return value;
  }
  std::string get_bytes() {
    const auto size = get<std::uint64_t>();
    need(size);
    std::string value = bytes_.substr(position_, size);
    position_ += size;
    return value;
  }
  /// A count of items of at least `bytes_each` bytes still to be read: more than the bytes
  /// that remain can hold is a damaged file, refused before anything is allocated for it.
  std::uint64_t get_count(std::uint64_t bytes_each) {
    const auto count = get<std::uint64_t>();
    if (count > (bytes_.size() - position_) / bytes_each)
      throw InputError(what_ + ": corrupt count " + std::to_string(count) + " at byte " +
                       std::to_string(position_ - sizeof count));
    return count;
  }
  std::size_t remaining() const { return bytes_.size() - position_; }
  bool at_end() const { return position_ == bytes_.size(); }

 private:
  void need(std::uint64_t size) const {
    if (size > bytes_.size() - position_) throw InputError(what_ + ": truncated at byte " + std::to_string(position_));
  }
  const std::string& bytes_;
  std::string what_;
  std::size_t position_ = 0;
};

}  // namespace slidespec::util
