#include "apps/lidar_odometry_cache.hpp"

#include "core/content_hash.hpp"

namespace statebench::app {
namespace {

constexpr char kStage[] = "lidar_odometry";
constexpr char kFile[] = "registrations.bin";

}  // namespace

std::string CachedRegistrationStore::EntryKey(const std::string& key) const {
  Sha256 h;
  h.Field("lidar odometry v1").Field(inputs_key_).Field(key);
  return h.Hex();
}

std::optional<std::vector<est::RecordedRegistration>> CachedRegistrationStore::Load(
    const std::string& key) {
  const std::optional<std::filesystem::path> entry = cache_.Find(kStage, EntryKey(key));
  if (!entry) return std::nullopt;
  return est::ReadRegistrations(*entry / kFile);
}

void CachedRegistrationStore::Save(const std::string& key,
                                   const std::vector<est::RecordedRegistration>& registrations) {
  cache_.Write(kStage, EntryKey(key), [&](const std::filesystem::path& written) {
    est::WriteRegistrations(written / kFile, registrations);
  });
}

}  // namespace statebench::app
