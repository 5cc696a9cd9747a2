// The job thread (src/runtime/job_thread.hpp): jobs in the order posted, and drain() as a barrier.
#include "runtime/job_thread.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <future>
#include <thread>
#include <vector>

namespace keel::runtime {
namespace {

TEST(JobThread, DrainReturnsOnlyOnceEveryJobPostedBeforeItHasRun) {
  JobThread thread;
  std::promise<void> release;
  std::shared_future<void> released = release.get_future().share();
  std::vector<int> ran;
  thread.post([released] { released.wait(); });  // holds the thread until released
  thread.post([&ran] { ran.push_back(1); });
  thread.post([&ran] { ran.push_back(2); });
  auto drained = std::async(std::launch::async, [&] { thread.drain(); });
  EXPECT_EQ(drained.wait_for(std::chrono::milliseconds(100)), std::future_status::timeout)
      << "drain() returned while a job posted before it had not run";
  release.set_value();
  ASSERT_EQ(drained.wait_for(std::chrono::seconds(30)), std::future_status::ready);
  EXPECT_EQ(ran, (std::vector<int>{1, 2}));
}

TEST(JobThread, DrainOnTheThreadItselfOrAfterStopReturnsAtOnce) {
  JobThread thread;
  std::promise<void> inner;
  thread.post([&] {
    thread.drain();  // would wait for itself
    inner.set_value();
  });
  auto done = inner.get_future();
  ASSERT_EQ(done.wait_for(std::chrono::seconds(30)), std::future_status::ready)
      << "drain() on the thread waited for itself";
  thread.stop();
  auto after = std::async(std::launch::async, [&] { thread.drain(); });
  EXPECT_EQ(after.wait_for(std::chrono::seconds(30)), std::future_status::ready)
      << "drain() after stop() waited forever";
}

}  // namespace
}  // namespace keel::runtime
