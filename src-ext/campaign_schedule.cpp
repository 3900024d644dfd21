#include "campaign_schedule.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <set>
#include <stdexcept>

#include "bed.hpp"

namespace ricochet::dem {

std::vector<int> schedule_order(const std::vector<std::string>& bed_keys,
                                const std::vector<char>& cached, int groups) {
  std::vector<int> order;
  const int n = static_cast<int>(bed_keys.size());
  if (groups == 1) {
    for (int i = 0; i < n; ++i) order.push_back(i);
    return order;
  }
  std::vector<std::string> beds;  // in the order of their first pending impact
  for (const auto& k : bed_keys)
    if (std::find(beds.begin(), beds.end(), k) == beds.end()) beds.push_back(k);
  const auto cached_bed = [&](const std::string& key) {
    for (int i = 0; i < n; ++i)
      if (bed_keys[static_cast<std::size_t>(i)] == key)
        return cached[static_cast<std::size_t>(i)] != 0;
    return false;
  };
  for (const bool first_pass : {true, false})
    for (const auto& key : beds) {
      if (cached_bed(key) != first_pass) continue;
      for (int i = 0; i < n; ++i)
        if (bed_keys[static_cast<std::size_t>(i)] == key) order.push_back(i);
    }
  return order;
}

namespace {

// An flock held for the object's lifetime on a file opened for reading and writing.
class LockedFile {
 public:
  explicit LockedFile(const std::string& path) : path_(path) {
    fd_ = ::open(path.c_str(), O_RDWR | O_CREAT, 0644);
    if (fd_ < 0) fail("cannot open");
    if (::flock(fd_, LOCK_EX) != 0) fail("cannot lock");
  }
  ~LockedFile() { ::close(fd_); }  // closing releases the lock
  LockedFile(const LockedFile&) = delete;
  LockedFile& operator=(const LockedFile&) = delete;
  std::string read_all() const {
    std::string text;
    char buf[4096];
    ::lseek(fd_, 0, SEEK_SET);
    for (ssize_t got; (got = ::read(fd_, buf, sizeof buf)) > 0;)
      text.append(buf, static_cast<std::size_t>(got));
    return text;
  }
  void append(const std::string& text) const {
    ::lseek(fd_, 0, SEEK_END);
    if (::write(fd_, text.data(), text.size()) != static_cast<ssize_t>(text.size()))
      fail("cannot write");
  }

 private:
  [[noreturn]] void fail(const char* what) const {
    throw std::runtime_error(std::string("campaign claims file ") + path_ + ": " + what + ": " +
                             std::strerror(errno));
  }
  std::string path_;
  int fd_ = -1;
};

}  // namespace

int claim_next(const std::string& claims_path, const std::vector<int>& order,
               const std::vector<std::string>& bed_keys, const std::string& cache_dir) {
  const LockedFile file(claims_path);
  std::set<int> claimed;
  const std::string text = file.read_all();
  for (std::size_t a = 0, b; (b = text.find('\n', a)) != std::string::npos; a = b + 1)
    claimed.insert(std::stoi(text.substr(a, b - a)));
  std::set<std::string> taken;  // beds that a claim of another group builds or waits for
  for (int c : claimed) {
    const std::string& key = bed_keys.at(static_cast<std::size_t>(c));
    if (!bed_cached(cache_dir, key)) taken.insert(key);
  }
  int pick = -1, unbuilt = -1, waiting = -1;
  for (int i : order) {
    if (claimed.count(i)) continue;
    const std::string& key = bed_keys.at(static_cast<std::size_t>(i));
    if (bed_cached(cache_dir, key)) {
      pick = i;
      break;
    }
    if (unbuilt < 0 && !taken.count(key) && !bed_building(cache_dir, key)) unbuilt = i;
    if (waiting < 0) waiting = i;
  }
  if (pick < 0) pick = unbuilt >= 0 ? unbuilt : waiting;
  if (pick >= 0) file.append(std::to_string(pick) + "\n");
  return pick;
}

}  // namespace ricochet::dem
