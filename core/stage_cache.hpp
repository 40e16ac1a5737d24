// A folder of cached pipeline stages (SUMO truth, sensor streams), each entry a folder named by
// the content hash of exactly what the stage depends on (docs/sweeps.md, "The stage cache").
//
//   <root>/<stage>/<key>/...          a complete entry (made complete by one rename)
//   <root>/<stage>/.tmp-<key>-<pid>/  an entry being written; left behind by a killed process,
//                                     removed by Prune once that process is gone
//
// Entries are written by whoever misses first and published with an atomic rename; when two
// processes compute the same entry, the first rename wins and the second copy is dropped, so
// readers only ever see complete entries. Lock() serialises the computation of one key across
// processes when computing it twice would waste much (flock on <root>/<stage>/<key>.lock).
// Prune() keeps the folder under its size limit by removing the least recently used entries.
// Nothing here prints; hit and miss counts are kept per stage for the run summary.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>

namespace statebench {

class StageCache {
 public:
  struct Counts {
    int hits = 0;
    int misses = 0;
  };

  // limit_bytes: Prune's target (0: no limit).
  StageCache(std::filesystem::path root, std::uint64_t limit_bytes);

  // The complete entry for (stage, key), counted as a hit (and marked used now), or nullopt,
  // counted as a miss.
  std::optional<std::filesystem::path> Find(const std::string& stage, const std::string& key);

  // An entry being written, over a whole run if need be (a stream recorded as it is simulated):
  // a fresh, empty folder now; Publish() renames it into place (or drops it when another
  // process was first) and returns the entry; destroyed unpublished (the stage did not
  // complete), the folder is removed.
  class PendingEntry {
   public:
    PendingEntry(PendingEntry&& other) noexcept;
    PendingEntry(const PendingEntry&) = delete;
    PendingEntry& operator=(const PendingEntry&) = delete;
    PendingEntry& operator=(PendingEntry&&) = delete;
    ~PendingEntry();

    const std::filesystem::path& folder() const { return folder_; }
    std::filesystem::path Publish();

   private:
    friend class StageCache;
    PendingEntry(const StageCache& cache, std::string stage, std::string key);

    const StageCache* cache_ = nullptr;  // nullptr once published or moved from
    std::string stage_, key_;
    std::filesystem::path folder_;
  };
  PendingEntry Begin(const std::string& stage, const std::string& key) const {
    return PendingEntry(*this, stage, key);
  }
  // Begin, write(folder), Publish (the folder is dropped if write throws). Returns the entry.
  std::filesystem::path Write(const std::string& stage, const std::string& key,
                              const std::function<void(const std::filesystem::path&)>& write) const;

  // An exclusive lock on (stage, key) across processes, released when the object is destroyed.
  class KeyLock {
   public:
    KeyLock(KeyLock&& other) noexcept : fd_(other.fd_) { other.fd_ = -1; }
    KeyLock(const KeyLock&) = delete;
    KeyLock& operator=(const KeyLock&) = delete;
    ~KeyLock();

   private:
    friend class StageCache;
    explicit KeyLock(int fd) : fd_(fd) {}
    int fd_ = -1;
  };
  KeyLock Lock(const std::string& stage, const std::string& key) const;

  // Removes the least recently used entries until the cache holds at most its limit, and the
  // unfinished folders of processes that no longer run. Returns the bytes removed.
  std::uint64_t Prune() const;

  const std::map<std::string, Counts>& counts() const { return counts_; }
  const std::filesystem::path& root() const { return root_; }

 private:
  std::filesystem::path root_;
  std::uint64_t limit_bytes_ = 0;
  std::map<std::string, Counts> counts_;
};

}  // namespace statebench
