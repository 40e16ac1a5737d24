#include "core/binary_io.hpp"

#include <algorithm>

namespace statebench {

BinaryWriter::BinaryWriter(const std::filesystem::path& path)
    : path_(path), out_(path, std::ios::binary | std::ios::trunc) {
  if (!out_) throw InputError(path.string() + ": cannot create");
}

BinaryWriter::~BinaryWriter() {
  if (!closed_) {
    Flush();  // best effort; Close() reports errors
  }
}

void BinaryWriter::PutBytes(const void* data, std::size_t size) {
  if (buffer_.size() + size > kWriteBytes) Flush();
  if (size >= kWriteBytes) {  // a lidar sweep: straight from its vector, in pieces
    WritePieces(static_cast<const char*>(data), size);
  } else {
    buffer_.append(static_cast<const char*>(data), size);
  }
}

void BinaryWriter::Flush() {
  WritePieces(buffer_.data(), buffer_.size());
  buffer_.clear();
}

void BinaryWriter::WritePieces(const char* data, std::size_t size) {
  for (std::size_t done = 0; done < size; done += kWriteBytes) {
    out_.write(data + done, static_cast<std::streamsize>(std::min(kWriteBytes, size - done)));
  }
}

void BinaryWriter::Close() {
  if (closed_) return;
  Flush();
  out_.close();
  closed_ = true;
  if (!out_) throw InputError(path_.string() + ": write failed");
}

BinaryReader::BinaryReader(const std::filesystem::path& path)
    : path_(path), in_(path, std::ios::binary) {
  std::error_code ec;
  size_ = std::filesystem::file_size(path, ec);
  if (!in_ || ec) throw InputError(path.string() + ": cannot open");
}

void BinaryReader::GetBytes(void* data, std::size_t size) {
  if (size > size_ - offset_) {
    throw InputError(path_.string() + ": truncated at byte " + std::to_string(offset_));
  }
  in_.read(static_cast<char*>(data), static_cast<std::streamsize>(size));
  if (static_cast<std::size_t>(in_.gcount()) != size) {
    throw InputError(path_.string() + ": read failed at byte " + std::to_string(offset_));
  }
  offset_ += size;
}

std::size_t BinaryReader::Count(std::size_t element_size) {
  const auto n = Get<std::uint64_t>();
  if (element_size > 0 && n > (size_ - offset_) / element_size) {
    throw InputError(path_.string() + ": bad length " + std::to_string(n) + " at byte " +
                     std::to_string(offset_));
  }
  return static_cast<std::size_t>(n);
}

}  // namespace statebench
