#pragma once
// Shared by FarmState's source files (farm_state*.cpp), not by its users: the
// transaction wrapper and the small conversions every query needs.
#include <mutex>
#include <type_traits>

#include "scheduler/farm_state.h"
#include "scheduler/schema.h"

namespace pathfarm::farm {

inline constexpr int kRunning = static_cast<int>(AttemptState::Running);

inline int64_t asInt(TaskState s) { return static_cast<int64_t>(s); }
inline int64_t asInt(AttemptState s) { return static_cast<int64_t>(s); }

inline bool isActive(ShotState state) { return state == SHOT_QUEUED || state == SHOT_RUNNING; }

// Tags as stored: ",a,b," (every tag between commas, so a lookup is one search), "" for none.
template <class Iterator>
std::string tagList(Iterator first, Iterator last) {
  std::string list;
  for (; first != last; ++first) list += "," + *first;
  return list.empty() ? list : list + ",";
}

template <class Body>
auto FarmState::transact(Body body) -> decltype(body()) {
  const std::lock_guard lock(mutex_);
  Transaction transaction(db_);
  if constexpr (std::is_void_v<decltype(body())>) {
    body();
    transaction.commit();
  } else {
    auto result = body();
    transaction.commit();
    return result;
  }
}

}  // namespace pathfarm::farm
