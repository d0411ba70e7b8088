#include "scheduler/farm_metrics.h"

#include <prometheus/metric_family.h>
#include <prometheus/text_serializer.h>

#include <limits>
#include <sstream>

namespace pathfarm::farm {
namespace {

using prometheus::ClientMetric;
using prometheus::MetricFamily;
using prometheus::MetricType;

MetricFamily family(const std::string& name, const std::string& help, MetricType type) {
  MetricFamily f;
  f.name = "pathfarm_" + name;
  f.help = help;
  f.type = type;
  return f;
}

ClientMetric gauge(std::vector<ClientMetric::Label> labels, double value) {
  ClientMetric m;
  m.label = std::move(labels);
  m.gauge.value = value;
  return m;
}

ClientMetric counter(std::vector<ClientMetric::Label> labels, double value) {
  ClientMetric m;
  m.label = std::move(labels);
  m.counter.value = value;
  return m;
}

}  // namespace

const std::vector<double>& durationBuckets() {
  static const std::vector<double> bounds = {0.1, 0.5, 1, 2, 5, 10, 30, 60, 300, 1800, 7200};
  return bounds;
}

std::string prometheusText(const FarmMetrics& m) {
  std::vector<MetricFamily> families;

  MetricFamily tasks = family("tasks", "Tasks by kind and state.", MetricType::Gauge);
  for (const auto& [key, count] : m.tasks)
    tasks.metric.push_back(gauge({{"kind", key.first}, {"state", key.second}}, static_cast<double>(count)));
  families.push_back(std::move(tasks));

  MetricFamily workers =
      family("workers", "Workers by state: busy (holding a lease), idle (asked for work lately), gone.", MetricType::Gauge);
  for (const auto& [state, count] : m.workers) workers.metric.push_back(gauge({{"state", state}}, static_cast<double>(count)));
  families.push_back(std::move(workers));

  MetricFamily durations = family("task_duration_seconds", "Lease to completion of the attempts that finished, by task kind.",
                                  MetricType::Histogram);
  for (const auto& [kind, d] : m.durations) {
    ClientMetric metric;
    metric.label = {{"kind", kind}};
    metric.histogram.sample_count = d.count;
    metric.histogram.sample_sum = d.sum;
    const std::vector<double>& bounds = durationBuckets();
    for (size_t b = 0; b < bounds.size() && b < d.cumulative.size(); ++b)
      metric.histogram.bucket.push_back({d.cumulative[b], bounds[b]});
    metric.histogram.bucket.push_back({d.count, std::numeric_limits<double>::infinity()});
    durations.metric.push_back(std::move(metric));
  }
  families.push_back(std::move(durations));

  MetricFamily ended = family("attempts_ended_total",
                              "Attempts that did not finish, by cause: failures the worker reported, by class "
                              "(worker_fault, bad_input, transport, released: handed back by a stopping worker), lost (the lease expired), revoked (hung, or "
                              "its shot ended).",
                              MetricType::Counter);
  for (const auto& [cause, count] : m.attemptsEnded) ended.metric.push_back(counter({{"cause", cause}}, static_cast<double>(count)));
  families.push_back(std::move(ended));

  MetricFamily shots = family("shots", "Shots by state.", MetricType::Gauge);
  for (const auto& [state, count] : m.shots) shots.metric.push_back(gauge({{"state", state}}, static_cast<double>(count)));
  families.push_back(std::move(shots));

  MetricFamily progress =
      family("shot_progress", "Share of its tasks done, for every queued or running shot.", MetricType::Gauge);
  for (const FarmMetrics::ShotProgress& p : m.progress)
    progress.metric.push_back(gauge({{"shot", std::to_string(p.id)}, {"name", p.name}}, p.done));
  families.push_back(std::move(progress));

  MetricFamily bytes = family("chunk_bytes_total", "Chunk bytes stored (in) and read (out) since the scheduler started.",
                              MetricType::Counter);
  bytes.metric.push_back(counter({{"direction", "in"}}, static_cast<double>(m.chunkBytesIn)));
  bytes.metric.push_back(counter({{"direction", "out"}}, static_cast<double>(m.chunkBytesOut)));
  families.push_back(std::move(bytes));

  std::ostringstream out;
  prometheus::TextSerializer().Serialize(out, families);
  return out.str();
}

}  // namespace pathfarm::farm
