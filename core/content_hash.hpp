// Content hashes: SHA-256 of bytes, strings and files, as lowercase hex.
//
// Used wherever an identity must follow exactly what determines a result: a sweep run's id (its
// resolved scenario, sensor setup, options, seed and code version) and the keys of the stage
// cache (SUMO truth, sensor streams). Feed the parts of a key with Field() so that ("ab", "c")
// and ("a", "bc") hash differently.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace statebench {

class Sha256 {
 public:
  Sha256();
  Sha256& Update(const void* data, std::size_t size);
  Sha256& Update(std::string_view text) { return Update(text.data(), text.size()); }
  // A length-prefixed part of a composite key.
  Sha256& Field(std::string_view text);
  // Adds the whole content of a file; throws InputError when it cannot be read.
  Sha256& File(const std::filesystem::path& path);
  // The digest as 64 hex characters; the hasher cannot be updated afterwards.
  std::string Hex();

 private:
  void Block(const std::uint8_t* block);

  std::array<std::uint32_t, 8> state_{};
  std::array<std::uint8_t, 64> buffer_{};
  std::size_t buffered_ = 0;
  std::uint64_t total_bytes_ = 0;
  bool finished_ = false;
};

std::string Sha256Hex(std::string_view text);
std::string Sha256OfFile(const std::filesystem::path& path);

}  // namespace statebench
