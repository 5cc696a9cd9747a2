// In-process delivery of fixed-size types does not allocate (issue: the hot path). Counted by
// replacing the global operator new for this test binary; only the test's own thread counts.
// GCC 12 warns that free() in a replacement operator delete mismatches operator new, although
// the replacement operator new above uses malloc: a known false positive for replacements.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"

#include <gtest/gtest.h>

#include <cstdlib>
#include <new>

#include "keel/component.hpp"
#include "support/recording_hooks.hpp"

namespace {
thread_local bool t_counting = false;
thread_local long t_allocations = 0;
}  // namespace

void* operator new(std::size_t n) {
  if (t_counting) ++t_allocations;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
// The nothrow forms too: under ASan the default nothrow new is ASan's, not a call of the
// replacement above, and memory from it must not reach the free() above.
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  if (t_counting) ++t_allocations;
  return std::malloc(n ? n : 1);
}
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }

namespace keel {
namespace {

struct Pose {
  double x, y, theta;
};

class Source : public Component {
 public:
  OutputDataPort<Pose> pose{this, "pose"};
  OutputDataPort<int> count{this, "count"};
};
class Target : public Component {
 public:
  InputDataPort<Pose> pose{this, "pose"};
  InputDataPort<int> count{this, "count"};
};

TEST(PortAllocation, PushAndPopOfFixedSizeTypesDoNotAllocate) {
  Source s;
  Target t1, t2;
  std::vector<std::unique_ptr<detail::ConnectionBase>> keep;
  test::wire(s.pose, t1.pose, keep);
  test::wire(s.pose, t2.pose, keep);  // fan-out
  test::wire(s.count, t1.count, keep);
  test::configureQueue(t1.pose, QueuePolicy::Fifo, 8);
  test::configureQueue(t2.pose, QueuePolicy::Last, 1);

  t_allocations = 0;
  t_counting = true;
  double sum = 0;
  for (int i = 0; i < 10000; ++i) {
    s.pose.push(Pose{double(i), 1.0, 0.5});
    s.count.push(i);
    if (auto p = t1.pose.pop()) sum += p->x;
    if (auto p = t2.pose.peek()) sum += p->y;
    if (auto c = t1.count.pop()) sum += *c;
  }
  t_counting = false;
  EXPECT_EQ(t_allocations, 0);
  EXPECT_GT(sum, 0.0);
}

TEST(PortAllocation, TheCounterSeesAnAllocation) {  // the instrument itself works
  t_allocations = 0;
  t_counting = true;
  int* volatile p = new int(3);  // volatile: the pair cannot be elided
  t_counting = false;
  delete p;
  EXPECT_EQ(t_allocations, 1);
}

}  // namespace
}  // namespace keel
