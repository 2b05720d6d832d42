#pragma once
// Flat binary records: trivially copyable values and vectors of them, length-prefixed, in the
// machine's byte order. For data that goes back to the same program (checkpoints, the pipe
// from the Gmsh reader's child process), not for exchange between machines.
#include <cstdint>
#include <cstring>
#include <functional>
#include <string>
#include <type_traits>
#include <vector>

namespace tc::core {

class ByteWriter {
 public:
  template <class T>
  void put(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    s_.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  template <class T>
  void put_vector(const std::vector<T>& v) {
    put(static_cast<std::uint64_t>(v.size()));
    s_.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
  void put_string(const std::string& v) {
    put(static_cast<std::uint64_t>(v.size()));
    s_ += v;
  }
  [[nodiscard]] std::string& str() { return s_; }

 private:
  std::string s_;
};

/// Reads what ByteWriter wrote; running past the end calls `fail` (which must throw the
/// caller's error: a damaged record is an error, not a crash).
class ByteReader {
 public:
  ByteReader(const std::string& s, std::function<void(const std::string&)> fail)
      : s_(s), fail_(std::move(fail)) {}
  template <class T>
  T get() {
    T v;
    need(sizeof v);
    std::memcpy(&v, s_.data() + pos_, sizeof v);
    pos_ += sizeof v;
    return v;
  }
  template <class T>
  std::vector<T> get_vector() {
    const auto n = get<std::uint64_t>();
    if (n > (s_.size() - pos_) / sizeof(T)) fail_("a vector runs past the end of the data");
    std::vector<T> v(n);
    std::memcpy(v.data(), s_.data() + pos_, n * sizeof(T));
    pos_ += n * sizeof(T);
    return v;
  }
  std::string get_string() {
    const auto n = get<std::uint64_t>();
    need(n);
    std::string v = s_.substr(pos_, n);
    pos_ += n;
    return v;
  }
  [[nodiscard]] std::size_t position() const { return pos_; }

 private:
  void need(std::size_t n) const {
    if (n > s_.size() - pos_) fail_("the data is truncated");
  }
  const std::string& s_;
  std::function<void(const std::string&)> fail_;
  std::size_t pos_ = 0;
};

}  // namespace tc::core
