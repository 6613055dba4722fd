#include "api/event_stream_slots.h"

namespace spheremap::api {

std::unique_ptr<EventStreamSlots::Slot> EventStreamSlots::acquire(
    const std::shared_ptr<EventStreamSlots>& slots, const std::string& tenant, int total,
    Refusal& refusal) {
  std::lock_guard lock(slots->mutex_);
  refusal = Refusal::kNone;
  if (slots->open_ >= total) {
    refusal = Refusal::kServerFull;
    return nullptr;
  }
  auto found = slots->by_tenant_.find(tenant);
  if (found != slots->by_tenant_.end() && found->second >= per_tenant(total)) {
    refusal = Refusal::kTenantFull;
    return nullptr;
  }
  ++slots->open_;
  ++slots->by_tenant_[tenant];
  return std::make_unique<Slot>(slots, tenant);
}

void EventStreamSlots::release(const std::string& tenant) {
  std::lock_guard lock(mutex_);
  --open_;
  auto found = by_tenant_.find(tenant);
  if (found != by_tenant_.end() && --found->second <= 0) by_tenant_.erase(found);
}

int EventStreamSlots::open() const {
  std::lock_guard lock(mutex_);
  return open_;
}

int EventStreamSlots::open(const std::string& tenant) const {
  std::lock_guard lock(mutex_);
  auto found = by_tenant_.find(tenant);
  return found == by_tenant_.end() ? 0 : found->second;
}

}  // namespace spheremap::api
