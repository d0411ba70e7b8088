#include "renderer/metropolis/mutation_stats.h"

#include <numeric>
#include <sstream>
#include <stdexcept>

#include "renderer/metropolis/exact_text.h"

namespace pathfarm {

MutationStats MutationStats::forKinds(std::vector<std::string> kindNames, int temporal) {
  MutationStats stats;
  stats.proposed.assign(kindNames.size(), 0);
  stats.accepted.assign(kindNames.size(), 0);
  stats.kinds = std::move(kindNames);
  stats.temporalKind = temporal;
  return stats;
}

uint64_t MutationStats::mutations() const { return std::accumulate(proposed.begin(), proposed.end(), uint64_t{0}); }

double MutationStats::acceptance(int kind) const {
  const auto k = static_cast<size_t>(kind);
  return proposed[k] > 0 ? static_cast<double>(accepted[k]) / static_cast<double>(proposed[k]) : 0;
}

void MutationStats::add(const MutationStats& other) {
  if (kinds.empty() && chains == 0) {
    *this = other;
    return;
  }
  if (other.kinds != kinds) throw std::invalid_argument("mutation statistics of different mutation kinds");
  for (size_t k = 0; k < kinds.size(); ++k) {
    proposed[k] += other.proposed[k];
    accepted[k] += other.accepted[k];
  }
  finalDeltaSum += other.finalDeltaSum;
  chains += other.chains;
}

void MutationStats::writeAttributes(FrameImage& image) const {
  auto& a = image.attributes();
  a["pathfarm.mlt.mutations"] = std::to_string(mutations());
  a["pathfarm.mlt.chains"] = std::to_string(chains);
  for (size_t k = 0; k < kinds.size(); ++k) {
    a["pathfarm.mlt.proposed." + kinds[k]] = std::to_string(proposed[k]);
    a["pathfarm.mlt.acceptance." + kinds[k]] = std::to_string(acceptance(static_cast<int>(k)));
  }
  if (temporalKind >= 0) {
    a["pathfarm.mlt.temporal_acceptance"] = std::to_string(temporalAcceptance());
    a["pathfarm.mlt.final_delta"] = std::to_string(meanFinalDelta());
  }
}

std::string MutationStats::serialize() const {
  std::ostringstream out;
  out << "pathfarm-mutation-stats 2\n"
      << "chains " << chains << " temporal " << temporalKind << " delta " << exactText(finalDeltaSum) << " kinds "
      << kinds.size() << '\n';
  for (size_t k = 0; k < kinds.size(); ++k) out << kinds[k] << ' ' << proposed[k] << ' ' << accepted[k] << '\n';
  return out.str();
}

MutationStats MutationStats::parse(const std::string& text) {
  std::istringstream in(text);
  std::string header, delta;
  std::getline(in, header);
  if (header != "pathfarm-mutation-stats 2") throw std::invalid_argument("mutation statistics: missing the header line");
  MutationStats stats;
  size_t count = 0;
  const auto expect = [&](const char* keyword) {
    std::string word;
    if (!(in >> word) || word != keyword)
      throw std::invalid_argument(std::string("mutation statistics: expected '") + keyword + "'");
  };
  expect("chains");
  in >> stats.chains;
  expect("temporal");
  in >> stats.temporalKind;
  expect("delta");
  in >> delta;
  expect("kinds");
  if (!(in >> count) || count > 64) throw std::invalid_argument("mutation statistics: bad kind count");
  stats.finalDeltaSum = parseExactText(delta, "mutation statistics");
  stats.kinds.resize(count);
  stats.proposed.resize(count);
  stats.accepted.resize(count);
  for (size_t k = 0; k < count; ++k)
    if (!(in >> stats.kinds[k] >> stats.proposed[k] >> stats.accepted[k]) || stats.accepted[k] > stats.proposed[k])
      throw std::invalid_argument("mutation statistics: bad counts of kind " + std::to_string(k));
  if (stats.temporalKind < -1 || stats.temporalKind >= static_cast<int>(count))
    throw std::invalid_argument("mutation statistics: bad temporal kind");
  return stats;
}

std::string MutationStats::summary() const {
  std::ostringstream out;
  out << mutations() << " mutations, acceptance";
  for (size_t k = 0; k < kinds.size(); ++k) out << ' ' << kinds[k] << ' ' << acceptance(static_cast<int>(k));
  if (temporalKind >= 0) out << ", final D " << meanFinalDelta() << " frames";
  return out.str();
}

}  // namespace pathfarm
