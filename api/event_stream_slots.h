// The event streams open at once (GET /v1/jobs/{id}/events): each holds an HTTP thread
// for as long as it lasts, so their number is capped for the server, and for each tenant
// at half of that, so that one tenant (or one address, without API keys) cannot take
// every slot and leave the others polling. Thread-safe.
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <string>

namespace spheremap::api {

class EventStreamSlots {
 public:
  // A slot held; given back when destroyed.
  class Slot {
   public:
    Slot(std::shared_ptr<EventStreamSlots> slots, std::string tenant)
        : slots_(std::move(slots)), tenant_(std::move(tenant)) {}
    ~Slot() { slots_->release(tenant_); }
    Slot(const Slot&) = delete;
    Slot& operator=(const Slot&) = delete;

   private:
    std::shared_ptr<EventStreamSlots> slots_;
    std::string tenant_;
  };

  enum class Refusal { kNone, kServerFull, kTenantFull };

  static int per_tenant(int total) { return total > 1 ? total / 2 : 1; }

  // A slot for `tenant` when fewer than `total` streams are open and fewer than
  // per_tenant(total) of them are the tenant's; else nullptr and why in `refusal`.
  static std::unique_ptr<Slot> acquire(const std::shared_ptr<EventStreamSlots>& slots,
                                       const std::string& tenant, int total, Refusal& refusal);

  int open() const;
  int open(const std::string& tenant) const;

 private:
  void release(const std::string& tenant);

  mutable std::mutex mutex_;
  int open_ = 0;
  std::map<std::string, int> by_tenant_;  // only tenants with a stream open
};

}  // namespace spheremap::api
