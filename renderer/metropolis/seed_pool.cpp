#include "renderer/metropolis/seed_pool.h"

#include <sstream>
#include <stdexcept>

#include "renderer/metropolis/exact_text.h"

namespace pathfarm {
namespace {

constexpr const char* kHeader = "pathfarm-seed-pool 1";

double parseExact(const std::string& token) { return parseExactText(token, "seed pool"); }

}  // namespace

std::string SeedPool::serialize() const {
  std::ostringstream out;
  out << kHeader << '\n'
      << "window " << window.first << ' ' << window.count << '\n'
      << "bootstrap " << bootstrapSamples << '\n'
      << "normalization " << exactText(normalization) << '\n'
      << "seeds " << seeds.size() << '\n';
  for (const ChainSeed& seed : seeds) out << seed.bootstrapIndex << ' ' << seed.strategy << ' ' << exactText(seed.contribution) << '\n';
  return out.str();
}

SeedPool SeedPool::parse(const std::string& text) {
  std::istringstream in(text);
  std::string line;
  if (!std::getline(in, line) || line != kHeader) throw std::invalid_argument("seed pool: missing the header line");
  SeedPool pool;
  const auto expect = [&](const char* keyword) {
    std::string word;
    if (!(in >> word) || word != keyword) throw std::invalid_argument(std::string("seed pool: expected '") + keyword + "'");
  };
  std::string number;
  size_t count = 0;
  expect("window");
  if (!(in >> pool.window.first >> pool.window.count) || pool.window.count < 1)
    throw std::invalid_argument("seed pool: bad window");
  expect("bootstrap");
  if (!(in >> pool.bootstrapSamples)) throw std::invalid_argument("seed pool: bad bootstrap sample count");
  expect("normalization");
  in >> number;
  pool.normalization = parseExact(number);
  if (!(pool.normalization >= 0)) throw std::invalid_argument("seed pool: negative normalization");
  expect("seeds");
  if (!(in >> count)) throw std::invalid_argument("seed pool: bad seed count");
  pool.seeds.resize(count);
  for (ChainSeed& seed : pool.seeds) {
    if (!(in >> seed.bootstrapIndex >> seed.strategy >> number)) throw std::invalid_argument("seed pool: truncated seed list");
    seed.contribution = parseExact(number);
  }
  if (in >> number) throw std::invalid_argument("seed pool: unexpected text after the seeds");
  return pool;
}

}  // namespace pathfarm
