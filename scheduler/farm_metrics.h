#pragma once
// The farm's figures for a monitoring stack, read from FarmState at scrape time (the same
// state the gRPC services serve: no second source of truth), and their Prometheus text
// exposition (prometheus-cpp's serializer).
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace pathfarm::farm {

struct FarmMetrics {
  // Tasks by (kind, state), kinds and states by their names (render_tile, ready, ...).
  std::map<std::pair<std::string, std::string>, int64_t> tasks;
  // Workers by state: busy (holding a lease), idle (asked for work lately), gone.
  std::map<std::string, int64_t> workers;
  // Durations (lease to completion) of the attempts that finished, by task kind:
  // cumulative counts at each of kDurationBuckets, the count and the sum.
  struct Durations {
    std::vector<uint64_t> cumulative;
    uint64_t count = 0;
    double sum = 0;
  };
  std::map<std::string, Durations> durations;
  // Attempts that did not finish, by cause: failed (the worker reported a failure),
  // lost (its lease expired), hung (revoked without progress), cancelled (its shot ended).
  std::map<std::string, int64_t> attemptsEnded;
  // Shots by state, and the share of tasks done of every queued or running shot.
  std::map<std::string, int64_t> shots;
  struct ShotProgress {
    int64_t id = 0;
    std::string name;
    double done = 0;  // 0..1
  };
  std::vector<ShotProgress> progress;
  uint64_t chunkBytesIn = 0, chunkBytesOut = 0;  // since the scheduler started
};

// Upper bounds (seconds) of the task duration histogram's buckets.
const std::vector<double>& durationBuckets();

// The Prometheus text format (version 0.0.4) of `metrics`, every name prefixed pathfarm_.
std::string prometheusText(const FarmMetrics& metrics);

}  // namespace pathfarm::farm
