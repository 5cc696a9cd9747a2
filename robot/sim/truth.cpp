// Ground-truth sharing through a seqlock in a mapped file: the writer makes the sequence odd,
// stores the words, makes it even; a reader retries until it sees the same even sequence
// before and after its copy. Every word is an atomic, so the protocol is race-free for TSan too.
#include "robot/sim/truth.hpp"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <bit>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <system_error>
#include <type_traits>

namespace keel::robot {
namespace {

constexpr std::size_t kWords = sizeof(TruthSample) / sizeof(std::uint64_t);
static_assert(sizeof(TruthSample) % sizeof(std::uint64_t) == 0 && std::is_trivially_copyable_v<TruthSample>);
static_assert(std::atomic<std::uint64_t>::is_always_lock_free, "shared across processes");

struct Shared {
  std::atomic<std::uint64_t> sequence;
  std::array<std::atomic<std::uint64_t>, kWords> words;
};

Shared& shared(void* map) { return *static_cast<Shared*>(map); }

}  // namespace

std::string truthPath(const std::string& name, long owner_pid) {
  return "/dev/shm/keel-" + name + "-" + std::to_string(owner_pid);
}

TruthWriter::TruthWriter(std::string path) : path_(std::move(path)) {
  const int fd = ::open(path_.c_str(), O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw std::runtime_error("cannot create " + path_ + ": " + std::generic_category().message(errno));
  if (::ftruncate(fd, sizeof(Shared)) != 0) {
    const int err = errno;
    ::close(fd);
    throw std::runtime_error("cannot size " + path_ + ": " + std::generic_category().message(err));
  }
  map_ = ::mmap(nullptr, sizeof(Shared), PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
  ::close(fd);
  if (map_ == MAP_FAILED) {
    map_ = nullptr;
    throw std::runtime_error("cannot map " + path_ + ": " + std::generic_category().message(errno));
  }
  new (map_) Shared{};  // zero: sequence 0 = nothing published yet
}

TruthWriter::~TruthWriter() {
  if (map_ != nullptr) ::munmap(map_, sizeof(Shared));
  ::unlink(path_.c_str());
}

void TruthWriter::publish(const TruthSample& sample) {
  const auto words = std::bit_cast<std::array<std::uint64_t, kWords>>(sample);
  Shared& s = shared(map_);
  const std::uint64_t seq = s.sequence.load(std::memory_order_relaxed);
  s.sequence.store(seq + 1, std::memory_order_relaxed);  // odd: being written
  // Release on each word: a reader that sees any new word also sees the odd sequence. (No
  // fences: TSan does not model them; on x86 these are plain stores either way.)
  for (std::size_t i = 0; i < kWords; ++i) s.words[i].store(words[i], std::memory_order_release);
  s.sequence.store(seq + 2, std::memory_order_release);  // even: consistent
}

TruthReader::~TruthReader() {
  if (map_ != nullptr) ::munmap(map_, sizeof(Shared));
}

std::optional<TruthSample> TruthReader::read() {
  if (map_ == nullptr) {
    const int fd = ::open(path_.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return std::nullopt;
    struct stat st {};
    if (::fstat(fd, &st) != 0 || st.st_size < static_cast<off_t>(sizeof(Shared))) {
      ::close(fd);
      return std::nullopt;  // being created
    }
    void* map = ::mmap(nullptr, sizeof(Shared), PROT_READ, MAP_SHARED, fd, 0);
    ::close(fd);
    if (map == MAP_FAILED) return std::nullopt;
    map_ = map;
  }
  const Shared& s = shared(map_);
  std::array<std::uint64_t, kWords> words{};
  for (int attempt = 0; attempt < 1000; ++attempt) {
    const std::uint64_t before = s.sequence.load(std::memory_order_acquire);
    if (before == 0) return std::nullopt;
    if (before % 2 != 0) continue;
    // Acquire on each word: the sequence is re-read after every word, never before.
    for (std::size_t i = 0; i < kWords; ++i) words[i] = s.words[i].load(std::memory_order_acquire);
    if (s.sequence.load(std::memory_order_relaxed) != before) continue;
    return std::bit_cast<TruthSample>(words);
  }
  return std::nullopt;  // a writer that never finishes: treat as no sample
}

}  // namespace keel::robot
