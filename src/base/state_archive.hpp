// Binary archives of a run's state (checkpoints, io/checkpoint.hpp): values and arrays of
// plain data written as their bytes, in the order one visitor function gives for both
// directions, so that saving and loading can never disagree on the layout.
//
//   template <class Archive> void visit(Archive& a, State& s) { a(s.x); a(s.array); }
//
// StateWriter appends to a byte string; StateReader reads it back and throws
// CheckpointError on any inconsistency (truncation, a size out of bounds), never reading
// past the end. Byte order and type sizes are those of the machine: a checkpoint resumes
// on the machine kind that wrote it (the header records what it needs to check this).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <cstring>
#include <functional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace geodem {

// A checkpoint that cannot be used (corrupt, truncated, another scenario's).
class CheckpointError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

namespace archive_detail {
template <typename T>
struct is_eigen_fixed : std::false_type {};
template <typename S, int R, int C, int O, int MR, int MC>
struct is_eigen_fixed<Eigen::Matrix<S, R, C, O, MR, MC>>
    : std::bool_constant<(R > 0 && C > 0 && std::is_arithmetic_v<S>)> {};
template <typename S, int O>
struct is_eigen_fixed<Eigen::Quaternion<S, O>> : std::is_arithmetic<S> {};
}  // namespace archive_detail

// Types stored as their bytes: arithmetic types, enums, fixed-size Eigen objects, and
// trivially copyable structs of those. A struct of Eigen members (not trivially copyable
// by the standard's rules, though plain bytes) opts in by specialising IsPlainData.
template <typename T>
struct IsPlainData : std::bool_constant<std::is_trivially_copyable_v<T> ||
                                        archive_detail::is_eigen_fixed<T>::value> {};
template <typename T>
inline constexpr bool kPlainData = IsPlainData<T>::value;

class StateWriter {
 public:
  static constexpr bool kLoading = false;
  // Where streamed bytes go (a file, a checksum, nowhere: a count).
  using Sink = std::function<void(const char*, std::size_t)>;

  StateWriter() = default;
  // Streams the bytes to `sink` instead of keeping them: bytes() stays empty, size()
  // counts them. A checkpoint's world goes this way, so that writing one needs no second
  // copy of the state in memory.
  explicit StateWriter(Sink sink) : sink_(std::move(sink)) {}

  template <typename T>
  void operator()(const T& v) {
    static_assert(kPlainData<T>, "not plain data: visit its fields");
    append(&v, sizeof(T));
  }
  template <typename T>
  void operator()(const std::vector<T>& v) {
    static_assert(kPlainData<T>, "not plain data: visit its fields");
    const std::uint64_t n = v.size();
    append(&n, sizeof n);
    if (n) append(v.data(), n * sizeof(T));
  }
  void operator()(const std::string& s) {
    const std::uint64_t n = s.size();
    append(&n, sizeof n);
    append(s.data(), s.size());
  }
  // Bytes as they are (no length prefix): an archive already made.
  void raw(const std::string& s) { append(s.data(), s.size()); }
  const std::string& bytes() const { return bytes_; }
  std::string& bytes() { return bytes_; }
  std::uint64_t size() const { return size_; }

 private:
  void append(const void* p, std::size_t n) {
    size_ += n;
    if (sink_)
      sink_(static_cast<const char*>(p), n);
    else
      bytes_.append(static_cast<const char*>(p), n);
  }
  std::string bytes_;
  Sink sink_;
  std::uint64_t size_ = 0;
};

class StateReader {
 public:
  static constexpr bool kLoading = true;

  StateReader(const char* data, std::size_t size) : p_(data), end_(data + size) {}

  template <typename T>
  void operator()(T& v) {
    static_assert(kPlainData<T>, "not plain data: visit its fields");
    take(&v, sizeof(T));
  }
  template <typename T>
  void operator()(std::vector<T>& v) {
    static_assert(kPlainData<T>, "not plain data: visit its fields");
    const std::uint64_t n = count(sizeof(T));
    v.resize(n);
    if (n) take(v.data(), n * sizeof(T));
  }
  void operator()(std::string& s) {
    const std::uint64_t n = count(1);
    s.assign(p_, n);
    p_ += n;
  }
  bool at_end() const { return p_ == end_; }
  std::size_t left() const { return static_cast<std::size_t>(end_ - p_); }

 private:
  // An element count, checked against the bytes left before anything is allocated.
  std::uint64_t count(std::size_t element_size) {
    std::uint64_t n = 0;
    take(&n, sizeof n);
    if (n > left() / element_size) throw CheckpointError("array length beyond the data");
    return n;
  }
  void take(void* out, std::size_t n) {
    if (n > left()) throw CheckpointError("truncated state");
    std::memcpy(out, p_, n);
    p_ += n;
  }
  const char* p_;
  const char* end_;
};

}  // namespace geodem
