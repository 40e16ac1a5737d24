// Little binary files of plain values, for caches: a writer that buffers and a reader that
// checks every read against the end of the file.
//
// Values are written in the machine's own representation (a cache is read back by the same
// build on the same machine; its key carries the build's identity), so a double comes back with
// the same bits. Strings and vectors are length-prefixed.
#pragma once

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <type_traits>
#include <vector>

#include "core/error.hpp"

namespace statebench {

class BinaryWriter {
 public:
  // Throws InputError when the file cannot be created.
  explicit BinaryWriter(const std::filesystem::path& path);
  ~BinaryWriter();
  BinaryWriter(const BinaryWriter&) = delete;
  BinaryWriter& operator=(const BinaryWriter&) = delete;

  template <typename T>
  void Put(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    PutBytes(&value, sizeof(T));
  }
  void PutString(const std::string& s) {
    Put<std::uint64_t>(s.size());
    PutBytes(s.data(), s.size());
  }
  template <typename T>
  void PutVector(const std::vector<T>& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    Put<std::uint64_t>(v.size());
    PutBytes(v.data(), v.size() * sizeof(T));
  }
  void PutBytes(const void* data, std::size_t size);
  // Flushes and closes; throws InputError when a write failed (disk full, ...).
  void Close();

 private:
  void Flush();
  // Every write() is at most kWriteBytes. Large writes cost the kernel far more per byte: 780 MB
  // of lidar sweeps written 1.3 MB at a time took 0.56-1.57 s of system time, in 64 KB pieces
  // 0.23-0.25 s (Linux 6.18, docs/sweeps.md "The stage cache").
  static constexpr std::size_t kWriteBytes = 64 * 1024;
  void WritePieces(const char* data, std::size_t size);
  std::filesystem::path path_;
  std::ofstream out_;
  std::string buffer_;
  bool closed_ = false;
};

class BinaryReader {
 public:
  // Opens the file (read in chunks as values are asked for); throws InputError when it cannot.
  explicit BinaryReader(const std::filesystem::path& path);

  template <typename T>
  T Get() {
    static_assert(std::is_trivially_copyable_v<T>);
    T value;
    GetBytes(&value, sizeof(T));
    return value;
  }
  std::string GetString() {
    std::string s(Count(1), '\0');
    GetBytes(s.data(), s.size());
    return s;
  }
  template <typename T>
  std::vector<T> GetVector() {
    std::vector<T> v(Count(sizeof(T)));
    GetBytes(v.data(), v.size() * sizeof(T));
    return v;
  }
  void GetBytes(void* data, std::size_t size);
  bool AtEnd() const { return offset_ == size_; }

 private:
  // A length prefix, checked against what is left of the file.
  std::size_t Count(std::size_t element_size);
  std::filesystem::path path_;
  std::ifstream in_;
  std::uint64_t size_ = 0;
  std::uint64_t offset_ = 0;
};

}  // namespace statebench
