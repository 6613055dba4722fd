// The event-stream cap (api/event_stream_slots.h): the server's total and each tenant's
// half of it, slots given back when a stream ends.
#include "api/event_stream_slots.h"

#include <gtest/gtest.h>

#include <vector>

namespace spheremap {
namespace {

using api::EventStreamSlots;

TEST(EventStreamSlots, OneTenantCannotTakeEverySlot) {
  auto slots = std::make_shared<EventStreamSlots>();
  EventStreamSlots::Refusal refusal;
  std::vector<std::unique_ptr<EventStreamSlots::Slot>> held;
  // Four for the server: two for tenant a, and its third is refused...
  for (int i = 0; i < 2; ++i) {
    held.push_back(EventStreamSlots::acquire(slots, "a", 4, refusal));
    ASSERT_TRUE(held.back()) << i;
  }
  EXPECT_FALSE(EventStreamSlots::acquire(slots, "a", 4, refusal));
  EXPECT_EQ(refusal, EventStreamSlots::Refusal::kTenantFull);
  // ...while tenant b still gets its two, and then the server is full for everyone.
  for (int i = 0; i < 2; ++i) {
    held.push_back(EventStreamSlots::acquire(slots, "b", 4, refusal));
    ASSERT_TRUE(held.back()) << i;
  }
  EXPECT_FALSE(EventStreamSlots::acquire(slots, "c", 4, refusal));
  EXPECT_EQ(refusal, EventStreamSlots::Refusal::kServerFull);
  EXPECT_EQ(slots->open(), 4);
  EXPECT_EQ(slots->open("a"), 2);
  // A stream that ends gives its slot back to its tenant and to the server.
  held.erase(held.begin());
  EXPECT_EQ(slots->open(), 3);
  EXPECT_EQ(slots->open("a"), 1);
  EXPECT_TRUE(EventStreamSlots::acquire(slots, "a", 4, refusal));  // and back at once
  EXPECT_EQ(refusal, EventStreamSlots::Refusal::kNone);
  held.clear();
  EXPECT_EQ(slots->open(), 0);
  EXPECT_EQ(slots->open("b"), 0);
}

TEST(EventStreamSlots, ASmallServerStillLetsEachTenantStream) {
  auto slots = std::make_shared<EventStreamSlots>();
  EventStreamSlots::Refusal refusal;
  // One slot in all (fewer than 8 HTTP threads): the tenant cap is that one.
  EXPECT_EQ(EventStreamSlots::per_tenant(1), 1);
  auto only = EventStreamSlots::acquire(slots, "a", 1, refusal);
  ASSERT_TRUE(only);
  EXPECT_FALSE(EventStreamSlots::acquire(slots, "b", 1, refusal));
  EXPECT_EQ(refusal, EventStreamSlots::Refusal::kServerFull);
  EXPECT_EQ(EventStreamSlots::per_tenant(5), 2);
}

}  // namespace
}  // namespace spheremap
