// RunEndLatch and the record of a run's end (runtime/run_end): the first request wins and
// wakes a waiter; the record holds keel's keys and the component's fields, or why not.
#include "engine/run_end.hpp"
#include "log/schema.hpp"

#include <gtest/gtest.h>

#include <thread>

namespace keel::engine {
namespace {

using namespace std::chrono_literals;

TEST(RunEndLatch, KeepsTheFirstRequestOnly) {
  RunEndLatch latch;
  EXPECT_FALSE(latch.requested());
  EXPECT_FALSE(latch.get());

  EXPECT_TRUE(latch.request({"referee", "goal reached", "mission", ""}));
  EXPECT_FALSE(latch.request({"other", "too late", "late", ""}));

  EXPECT_TRUE(latch.requested());
  ASSERT_TRUE(latch.get());
  EXPECT_EQ(latch.get()->component, "referee");
  EXPECT_EQ(latch.get()->summary, "goal reached");
}

TEST(RunEndLatch, WakesAWaiterAtOnce) {
  RunEndLatch latch;
  EXPECT_FALSE(latch.waitUntil(std::chrono::steady_clock::now() + 10ms));
  std::thread requester([&] {
    std::this_thread::sleep_for(20ms);
    (void)latch.request({"referee", "done", "", ""});
  });
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_TRUE(latch.waitUntil(t0 + 30s));
  EXPECT_LT(std::chrono::steady_clock::now() - t0, 10s);
  requester.join();
}

TEST(RunEndRecord, HoldsKeelsKeysAndTheFields) {
  const auto r = runEndRecord({"referee", "s", "mission", R"("goal_reached":true,"collisions":0)"}, 42);
  EXPECT_EQ(r, nlohmann::json::parse(
                   R"({"t_ns":42,"event":"mission","component":"referee","goal_reached":true,"collisions":0})"));
}

TEST(RunEndRecord, KeelsKeysWinOverFieldsOfTheSameName) {
  const auto r = runEndRecord({"referee", "s", "mission", R"("event":"x","t_ns":1,"n":2)"}, 42);
  EXPECT_EQ(r, nlohmann::json::parse(R"({"t_ns":42,"event":"mission","component":"referee","n":2})"));
}

TEST(RunEndRecord, EmptyFieldsGiveJustKeelsKeys) {
  const auto r = runEndRecord({"referee", "s", "mission", ""}, 7);
  EXPECT_EQ(r, nlohmann::json::parse(R"({"t_ns":7,"event":"mission","component":"referee"})"));
}

TEST(RunEndRecord, MalformedFieldsGiveAFieldsErrorNamingThem) {
  for (const char* bad : {R"("a":1,)", R"("a":1}, {"b":2)", R"({"a":1})", "a:1", R"("a":1 "b":2)"}) {
    const auto r = runEndRecord({"referee", "s", "mission", bad}, 7);
    ASSERT_TRUE(r.contains(log::schema::field::kFieldsError)) << bad;
    EXPECT_EQ(r[log::schema::field::kFieldsError].get<std::string>().rfind(
                  std::string("fields_json '") + bad + "' is not the members of a JSON object: ", 0),
              0u)
        << r.dump();
    EXPECT_EQ(r.size(), 4u) << r.dump();  // t_ns, event, component, fields_error
  }
}

}  // namespace
}  // namespace keel::engine
