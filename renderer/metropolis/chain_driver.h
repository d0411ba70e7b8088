#pragma once
// Runs Markov chains of any target (chain_target.h) over a window of frames: the
// bootstrap that yields the seed pool, and blocks of chains with expected-value splatting
// (Veach 1997, 11.5: the current and the proposed state both splat, weighted 1 - a and
// a), per-kind acceptance counts and the optional tuning of the temporal reach D.
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>

#include "renderer/metropolis/block_result.h"
#include "renderer/metropolis/chain_settings.h"
#include "renderer/metropolis/chain_streams.h"
#include "renderer/metropolis/chain_target.h"
#include "renderer/metropolis/delta_tuner.h"
#include "renderer/metropolis/seed_choice.h"
#include "renderer/metropolis/window_films.h"

namespace pathfarm {

// Called as chains finish: (chains done, chains in the block).
using ChainProgress = std::function<void(size_t, size_t)>;

template <ChainTarget Target>
class ChainDriver {
 public:
  using State = typename Target::State;

  ChainDriver(const Target& target, const WindowTime& time, ChainSettings settings)
      : target_(target), time_(time), settings_(settings) {
    settings_.validate();
  }

  const ChainSettings& settings() const { return settings_; }

  // The bootstrap: settings.bootstrapSamplesOf(window) independent samples of every strategy.
  SeedPool seedPool() const {
    const int strategies = target_.strategies();
    const uint64_t samples = settings_.bootstrapSamplesOf(time_.window());
    std::vector<double> scalars(samples * static_cast<uint64_t>(strategies));
    inArena([&] {
      tbb::parallel_for(uint64_t{0}, samples, [&](uint64_t i) {
        for (int s = 0; s < strategies; ++s) {
          SampleStream random = bootstrapStream(settings_.sceneSeed, time_.window(), i, s, strategies);
          scalars[i * static_cast<uint64_t>(strategies) + static_cast<uint64_t>(s)] =
              target_.bootstrap(s, random).contribution.scalar();
        }
      });
    });
    SeedPool pool = chooseSeeds(time_.window(), settings_.sceneSeed, strategies, scalars, settings_.chains);
    pool.bootstrapSamples = samples;
    return pool;
  }

  // Chains [block * chainsPerBlock, ...) of the window, in parallel; the frames hold this
  // block's share of the radiance estimate.
  BlockResult runBlock(const SeedPool& pool, int block, const ChainProgress& progress = {}) const {
    checkPool(pool, block);
    const int first = block * settings_.chainsPerBlock;
    const int count = std::min(settings_.chainsPerBlock, settings_.chains - first);
    const FrameWindow window = time_.window();
    WindowFilms films(window, settings_.width, settings_.height);
    std::vector<MutationStats> stats(static_cast<size_t>(count), emptyStats());
    std::atomic<size_t> done{0};
    if (!pool.seeds.empty())
      inArena([&] {
        tbb::parallel_for(0, count, [&](int i) {
          runChain(pool, first + i, films, stats[static_cast<size_t>(i)]);
          const size_t finished = ++done;
          if (progress) progress(finished, static_cast<size_t>(count));
        });
      });
    BlockResult result;
    result.block = block;
    result.frames = films.toImages(settings_.filmScale(window, pool.normalization));
    result.stats = emptyStats();
    for (const MutationStats& s : stats) result.stats.add(s);
    return result;
  }

 private:
  MutationStats emptyStats() const { return MutationStats::forKinds(target_.mutationKinds(), target_.temporalKind()); }

  template <class Work>
  void inArena(const Work& work) const {
    tbb::task_arena arena(settings_.threads > 0 ? settings_.threads : tbb::task_arena::automatic);
    arena.execute(work);
  }

  void checkPool(const SeedPool& pool, int block) const {
    if (block < 0 || block >= settings_.blocks())
      throw std::invalid_argument("block " + std::to_string(block) + " does not exist (the window has " +
                                  std::to_string(settings_.blocks()) + " blocks)");
    if (pool.window.first != time_.window().first || pool.window.count != time_.window().count)
      throw std::invalid_argument("the seed pool belongs to another window");
    if (!pool.seeds.empty() && pool.seeds.size() != static_cast<size_t>(settings_.chains))
      throw std::invalid_argument("the seed pool holds " + std::to_string(pool.seeds.size()) + " seeds for " +
                                  std::to_string(settings_.chains) + " chains");
  }

  // The seed regenerated from its bootstrap stream; its contribution must be the one the
  // pool recorded, or the pool came from another scene or other settings.
  State regenerate(const ChainSeed& seed) const {
    SampleStream random =
        bootstrapStream(settings_.sceneSeed, time_.window(), seed.bootstrapIndex, seed.strategy, target_.strategies());
    State state = target_.bootstrap(seed.strategy, random);
    const double scalar = state.contribution.scalar();
    if (!(std::abs(scalar - seed.contribution) <= 1e-6 * seed.contribution))
      throw std::invalid_argument("a chain seed does not regenerate to the contribution the seed pool recorded: the "
                                  "pool was made for another scene or other settings");
    return state;
  }

  void runChain(const SeedPool& pool, int chain, WindowFilms& films, MutationStats& stats) const {
    State current = regenerate(pool.seeds[static_cast<size_t>(chain)]);
    const uint64_t mutations = settings_.mutationsOfChain(time_.window(), chain);
    SampleStream random = chainStream(settings_.sceneSeed, time_.window(), static_cast<uint32_t>(chain));
    DeltaTuner tuner(settings_.temporalDelta, time_.window().count, settings_.tuneDelta,
                     settings_.targetTemporalAcceptance,
                     static_cast<uint64_t>(settings_.tuningShare * static_cast<double>(mutations)));
    const int temporalKind = target_.temporalKind();
    for (uint64_t m = 0; m < mutations; ++m) {
      const TemporalProposal temporal(time_, tuner.delta());
      MutationContext context{random, temporal};
      Proposal<State> proposal = target_.propose(current, context);
      const double a = acceptance(current.contribution.scalar(), proposal);
      films.splat(current.contribution, 1 - a);
      films.splat(proposal.state.contribution, a);
      const auto kind = static_cast<size_t>(proposal.kind);
      ++stats.proposed[kind];
      if (proposal.kind == temporalKind) tuner.observe(m, a);
      if (random.next1D() < a) {
        ++stats.accepted[kind];
        current = std::move(proposal.state);
      }
    }
    stats.finalDeltaSum = tuner.delta();
    stats.chains = 1;
  }

  // The Metropolis-Hastings acceptance min(1, f(y) T(y->x) / (f(x) T(x->y))).
  static double acceptance(double currentScalar, const Proposal<State>& proposal) {
    const double proposed = proposal.state.contribution.scalar();
    if (!(proposed > 0)) return 0;
    if (!(currentScalar > 0)) return 1;
    const double a = proposed * proposal.transitionRatio / currentScalar;
    return std::isfinite(a) ? std::min(1.0, a) : (a > 0 ? 1.0 : 0.0);
  }

  const Target& target_;
  const WindowTime& time_;
  ChainSettings settings_;
};

}  // namespace pathfarm
