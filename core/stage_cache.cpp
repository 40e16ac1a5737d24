#include "core/stage_cache.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <utility>
#include <vector>

#include "core/error.hpp"

namespace statebench {
namespace {

namespace fs = std::filesystem;

constexpr const char* kTmpPrefix = ".tmp-";

std::uint64_t FolderBytes(const fs::path& dir) {
  std::uint64_t bytes = 0;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(dir, ec); !ec && it != fs::end(it);
       it.increment(ec)) {
    if (it->is_regular_file(ec)) bytes += it->file_size(ec);
  }
  return bytes;
}

bool ProcessAlive(long pid) { return pid > 0 && (kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM); }

}  // namespace

StageCache::StageCache(fs::path root, std::uint64_t limit_bytes)
    : root_(std::move(root)), limit_bytes_(limit_bytes) {
  std::error_code ec;
  fs::create_directories(root_, ec);
  if (ec) throw InputError(root_.string() + ": cannot create the cache folder: " + ec.message());
}

std::optional<fs::path> StageCache::Find(const std::string& stage, const std::string& key) {
  const fs::path entry = root_ / stage / key;
  std::error_code ec;
  if (fs::is_directory(entry, ec)) {
    ++counts_[stage].hits;
    fs::last_write_time(entry, fs::file_time_type::clock::now(), ec);  // least recently used
    return entry;
  }
  ++counts_[stage].misses;
  return std::nullopt;
}

StageCache::PendingEntry::PendingEntry(const StageCache& cache, std::string stage,
                                       std::string key)
    : cache_(&cache),
      stage_(std::move(stage)),
      key_(std::move(key)),
      folder_(cache.root_ / stage_ /
              (std::string(kTmpPrefix) + key_ + "-" + std::to_string(getpid()))) {
  std::error_code ec;
  fs::remove_all(folder_, ec);
  fs::create_directories(folder_, ec);
  if (ec) throw InputError(folder_.string() + ": cannot create: " + ec.message());
}

StageCache::PendingEntry::PendingEntry(PendingEntry&& other) noexcept
    : cache_(std::exchange(other.cache_, nullptr)),
      stage_(std::move(other.stage_)),
      key_(std::move(other.key_)),
      folder_(std::move(other.folder_)) {}

StageCache::PendingEntry::~PendingEntry() {
  if (cache_ == nullptr) return;
  std::error_code ec;
  fs::remove_all(folder_, ec);
}

fs::path StageCache::PendingEntry::Publish() {
  const fs::path entry = cache_->root_ / stage_ / key_;
  std::error_code ec;
  fs::rename(folder_, entry, ec);
  if (ec) fs::remove_all(folder_, ec);  // another process published it first
  cache_ = nullptr;
  return entry;
}

fs::path StageCache::Write(const std::string& stage, const std::string& key,
                          const std::function<void(const fs::path&)>& write) const {
  PendingEntry entry = Begin(stage, key);
  write(entry.folder());
  return entry.Publish();
}

StageCache::KeyLock::~KeyLock() {
  if (fd_ >= 0) {
    flock(fd_, LOCK_UN);
    close(fd_);
  }
}

StageCache::KeyLock StageCache::Lock(const std::string& stage, const std::string& key) const {
  const fs::path dir = root_ / stage;
  std::error_code ec;
  fs::create_directories(dir, ec);
  const fs::path file = dir / (key + ".lock");
  const int fd = open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) throw InputError(file.string() + ": cannot create the lock file");
  while (flock(fd, LOCK_EX) != 0 && errno == EINTR) {
  }
  return KeyLock(fd);
}

std::uint64_t StageCache::Prune() const {
  struct Entry {
    fs::path path;
    fs::file_time_type used;
    std::uint64_t bytes = 0;
  };
  std::vector<Entry> entries;
  std::uint64_t total = 0, removed = 0;
  std::error_code ec;
  for (const auto& stage : fs::directory_iterator(root_, ec)) {
    if (!stage.is_directory(ec)) continue;
    for (const auto& item : fs::directory_iterator(stage.path(), ec)) {
      const std::string name = item.path().filename().string();
      if (!item.is_directory(ec)) continue;
      if (name.rfind(kTmpPrefix, 0) == 0) {
        const long pid = std::atol(name.substr(name.rfind('-') + 1).c_str());
        if (!ProcessAlive(pid)) {
          removed += FolderBytes(item.path());
          fs::remove_all(item.path(), ec);
        }
        continue;
      }
      Entry e{item.path(), fs::last_write_time(item.path(), ec), FolderBytes(item.path())};
      total += e.bytes;
      entries.push_back(std::move(e));
    }
  }
  if (limit_bytes_ == 0 || total <= limit_bytes_) return removed;
  std::sort(entries.begin(), entries.end(),
            [](const Entry& a, const Entry& b) { return a.used < b.used; });
  for (const Entry& e : entries) {
    if (total <= limit_bytes_) break;
    fs::remove_all(e.path, ec);
    total -= e.bytes;
    removed += e.bytes;
  }
  return removed;
}

}  // namespace statebench
