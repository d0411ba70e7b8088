#include "scheduler/farm_names.h"

#include <algorithm>
#include <array>
#include <cctype>

#include "scheduler/schema.h"

namespace pathfarm::farm {
namespace {

constexpr std::array<const char*, 5> kTaskStates = {"waiting", "ready", "leased", "done", "failed"};
constexpr std::array<const char*, 5> kAttemptStates = {"running", "done", "failed", "expired", "revoked"};
static_assert(static_cast<int>(TaskState::Failed) == 4 && static_cast<int>(AttemptState::Revoked) == 4,
              "the names above follow scheduler/schema.h's enums in order");

template <size_t N>
std::string nameIn(const std::array<const char*, N>& names, int value) {
  return value >= 0 && static_cast<size_t>(value) < N ? names[static_cast<size_t>(value)] : "unknown";
}

}  // namespace

std::string lowerWithout(const std::string& name, const std::string& prefix) {
  std::string text = name.rfind(prefix, 0) == 0 ? name.substr(prefix.size()) : name;
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

std::string taskStateName(int state) { return nameIn(kTaskStates, state); }
std::string attemptStateName(int state) { return nameIn(kAttemptStates, state); }

std::optional<int> taskStateByName(const std::string& name) {
  for (size_t i = 0; i < kTaskStates.size(); ++i)
    if (name == kTaskStates[i]) return static_cast<int>(i);
  return std::nullopt;
}

}  // namespace pathfarm::farm
