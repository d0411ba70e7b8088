#include "scheduler/farm_clock.h"

#include <gtest/gtest.h>

#include <cmath>

namespace pathfarm::farm {
namespace {

using namespace std::chrono_literals;

TEST(FarmClock, AStepOfTheWallClockDoesNotMoveIt) {
  auto wall = std::chrono::system_clock::time_point(1'800'000'000s);
  auto steady = std::chrono::steady_clock::time_point(5000s);
  const FarmClock clock([&] { return wall; }, [&] { return steady; });
  EXPECT_DOUBLE_EQ(clock.seconds(), 1.8e9);
  // Ten seconds pass; meanwhile the wall clock is set back an hour, then forward a day.
  steady += 10s;
  wall -= 1h;
  EXPECT_DOUBLE_EQ(clock.seconds(), 1.8e9 + 10);
  wall += 24h;
  steady += 2500ms;
  EXPECT_DOUBLE_EQ(clock.seconds(), 1.8e9 + 12.5);
}

TEST(FarmClock, ItStartsAtTheWallClock) {
  const double wall = std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
  EXPECT_LT(std::abs(farmClockSeconds() - wall), 1.0);
}

}  // namespace
}  // namespace pathfarm::farm
