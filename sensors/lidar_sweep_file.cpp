#include "sensors/lidar_sweep_file.hpp"

#include <zstd.h>

#include <array>
#include <cstring>
#include <memory>
#include <string>

#include "core/error.hpp"
#include "sensors/file_bytes.hpp"
#include "sensors/lidar_sweep_codec.hpp"

namespace statebench::sensors {
namespace {

namespace fs = std::filesystem;

constexpr char kMagic[8] = {'S', 'B', 'S', 'W', 'E', 'E', 'P', '\0'};
constexpr std::uint32_t kVersion = 1;
constexpr std::size_t kHeaderBytes = 16 + 4 * kSweepFieldCount;
constexpr int kCompressionLevel = 3;  // zstd's default: 0.18 of a binary PCD, ~5 ms per sweep

[[noreturn]] void FailSweepFile(const fs::path& file, const std::string& what) {
  throw InputError(file.string() + ": " + what);
}

[[noreturn]] void FailField(const fs::path& file, std::size_t f, const std::string& what) {
  FailSweepFile(file, "field '" + std::string(SweepFieldName(static_cast<SweepField>(f))) + "': " + what);
}

std::uint32_t Get32(const std::uint8_t* in) { return GetLittleEndian<std::uint32_t>(in); }

// zstd contexts and buffers, one set per thread, reused from sweep to sweep.
struct CompressionContext {
  CompressionContext() : context(ZSTD_createCCtx(), ZSTD_freeCCtx) {
    ZSTD_CCtx_setParameter(context.get(), ZSTD_c_compressionLevel, kCompressionLevel);
    ZSTD_CCtx_setParameter(context.get(), ZSTD_c_checksumFlag, 1);
    ZSTD_CCtx_setParameter(context.get(), ZSTD_c_contentSizeFlag, 1);
  }
  std::unique_ptr<ZSTD_CCtx, std::size_t (*)(ZSTD_CCtx*)> context;
  SweepPlanes planes;
  std::vector<std::uint8_t> bytes;
};

struct DecompressionContext {
  DecompressionContext() : context(ZSTD_createDCtx(), ZSTD_freeDCtx) {}
  std::unique_ptr<ZSTD_DCtx, std::size_t (*)(ZSTD_DCtx*)> context;
  SweepPlanes planes;
  std::vector<std::uint8_t> bytes;
};

// Decompresses field f's frame, bytes [begin, begin + size) of the file, into its planes.
void DecompressField(const fs::path& file, std::size_t f, const std::uint8_t* frame,
                     std::size_t size, std::size_t points, DecompressionContext& z) {
  const std::size_t expected = SweepFieldBytes(static_cast<SweepField>(f), points);
  const unsigned long long content = ZSTD_getFrameContentSize(frame, size);
  if (content == ZSTD_CONTENTSIZE_ERROR || content == ZSTD_CONTENTSIZE_UNKNOWN) {
    FailField(file, f, "not a zstd frame with its content size");
  }
  if (content != expected) {
    FailField(file, f,
              "its frame holds " + std::to_string(content) + " bytes, " +
                  std::to_string(points) + " points need " + std::to_string(expected));
  }
  if (ZSTD_findFrameCompressedSize(frame, size) != size) {
    FailField(file, f, "its " + std::to_string(size) + " bytes are not exactly one zstd frame");
  }
  std::vector<std::uint8_t>& plane = z.planes[f];
  plane.resize(expected);
  const std::size_t got = ZSTD_decompressDCtx(z.context.get(), plane.data(), plane.size(), frame,
                                              size);
  if (ZSTD_isError(got)) {
    FailField(file, f, std::string("corrupt compressed data (zstd: ") + ZSTD_getErrorName(got) +
                           ")");
  }
  if (got != expected) {
    FailField(file, f, "decompresses to " + std::to_string(got) + " bytes, expected " +
                           std::to_string(expected));
  }
}

}  // namespace

void WriteLidarSweepFile(const fs::path& file, const std::vector<LidarPoint>& points) {
  if (points.size() > kMaxSweepFilePoints) {
    FailSweepFile(file, std::to_string(points.size()) + " points, a sweep file holds at most " +
                   std::to_string(kMaxSweepFilePoints));
  }
  thread_local CompressionContext z;
  EncodeSweep(points, z.planes);
  std::size_t bound = kHeaderBytes;
  for (const auto& plane : z.planes) bound += ZSTD_compressBound(plane.size());
  z.bytes.resize(bound);
  std::uint8_t* out = z.bytes.data();
  std::memcpy(out, kMagic, sizeof(kMagic));
  PutLittleEndian(out + 8, kVersion);
  PutLittleEndian(out + 12, static_cast<std::uint32_t>(points.size()));
  std::size_t at = kHeaderBytes;
  for (std::size_t f = 0; f < kSweepFieldCount; ++f) {
    const std::size_t size = ZSTD_compress2(z.context.get(), out + at, bound - at,
                                            z.planes[f].data(), z.planes[f].size());
    if (ZSTD_isError(size)) FailField(file, f, std::string("zstd: ") + ZSTD_getErrorName(size));
    PutLittleEndian(out + 16 + 4 * f, static_cast<std::uint32_t>(size));
    at += size;
  }
  WriteFileBytes(file, out, at);
}

std::vector<LidarPoint> ReadLidarSweepFile(const fs::path& file) {
  thread_local DecompressionContext z;
  ReadFileBytes(file, z.bytes);
  const std::uint8_t* in = z.bytes.data();
  const std::size_t size = z.bytes.size();
  if (size < kHeaderBytes) {
    if (size >= sizeof(kMagic) && std::memcmp(in, kMagic, sizeof(kMagic)) != 0) {
      FailSweepFile(file, "not a StateBench sweep file (its first bytes are not \"SBSWEEP\")");
    }
    FailSweepFile(file, "truncated: " + std::to_string(size) + " bytes, a sweep file's header takes " +
                   std::to_string(kHeaderBytes));
  }
  if (std::memcmp(in, kMagic, sizeof(kMagic)) != 0) {
    FailSweepFile(file, "not a StateBench sweep file (its first bytes are not \"SBSWEEP\")");
  }
  if (const std::uint32_t version = Get32(in + 8); version != kVersion) {
    FailSweepFile(file, "sweep file version " + std::to_string(version) + ", this reader knows " +
                   std::to_string(kVersion));
  }
  const std::uint32_t points = Get32(in + 12);
  if (points > kMaxSweepFilePoints) {
    FailSweepFile(file, "announces " + std::to_string(points) + " points, at most " +
                   std::to_string(kMaxSweepFilePoints));
  }
  std::size_t at = kHeaderBytes;
  for (std::size_t f = 0; f < kSweepFieldCount; ++f) {
    const std::size_t frame = Get32(in + 16 + 4 * f);
    if (frame > size - at) {
      FailField(file, f, "truncated: its frame takes bytes " + std::to_string(at) + " to " +
                             std::to_string(at + frame) + ", the file ends at " +
                             std::to_string(size));
    }
    DecompressField(file, f, in + at, frame, points, z);
    at += frame;
  }
  if (at != size) {
    FailSweepFile(file, std::to_string(size - at) + " bytes after its last field (a sweep file ends with "
                                            "the intensity frame)");
  }
  std::vector<LidarPoint> out;
  DecodeSweep(z.planes, points, out);
  return out;
}

}  // namespace statebench::sensors
