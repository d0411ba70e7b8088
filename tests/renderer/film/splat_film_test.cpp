#include "renderer/film/splat_film.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <thread>
#include <vector>

namespace pathfarm {
namespace {

struct Splat {
  int x, y;
  Rgb value;
};

std::vector<Splat> randomSplats(size_t count) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> pixel(0, 7);
  std::uniform_real_distribution<float> value(0.0f, 3.0f);
  std::vector<Splat> splats;
  for (size_t i = 0; i < count; ++i) splats.push_back({pixel(rng), pixel(rng), Rgb(value(rng), value(rng), value(rng))});
  return splats;
}

FrameImage filmOf(const std::vector<Splat>& splats, int threads) {
  SplatFilm film(8, 8);
  std::vector<std::thread> workers;
  for (int t = 0; t < threads; ++t)
    workers.emplace_back([&, t] {
      for (size_t i = static_cast<size_t>(t); i < splats.size(); i += static_cast<size_t>(threads))
        film.add(splats[i].x, splats[i].y, splats[i].value);
    });
  for (auto& w : workers) w.join();
  return film.toImage();
}

TEST(SplatFilm, BitsDoNotDependOnOrderOrThreads) {
  std::vector<Splat> splats = randomSplats(20000);
  const FrameImage oneThread = filmOf(splats, 1);
  std::reverse(splats.begin(), splats.end());
  const FrameImage reversed = filmOf(splats, 4);
  for (const char* c : {"R", "G", "B"}) EXPECT_EQ(oneThread.channel(c), reversed.channel(c));
}

TEST(SplatFilm, SumsMatchDoublePrecisionWithinTheRoundingOfEachSplat) {
  const std::vector<Splat> splats = randomSplats(5000);
  std::vector<double> expected(64 * 3, 0.0);
  for (const Splat& s : splats)
    for (int c = 0; c < 3; ++c) expected[3 * static_cast<size_t>(s.y * 8 + s.x) + static_cast<size_t>(c)] += s.value[c];
  SplatFilm film(8, 8);
  for (const Splat& s : splats) film.add(s.x, s.y, s.value);
  const double bound = 0.5 * SplatFilm::kResolution * static_cast<double>(splats.size());
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x)
      for (int c = 0; c < 3; ++c) {
        const double want = expected[3 * static_cast<size_t>(y * 8 + x) + static_cast<size_t>(c)];
        // The film returns floats: their rounding adds a relative 2^-24.
        EXPECT_NEAR(film.value(x, y)[c], want, bound + want * 0x1p-23);
      }
}

TEST(SplatFilm, MergingFilmsEqualsAddingEverySplatToOne) {
  const std::vector<Splat> splats = randomSplats(3000);
  SplatFilm whole(8, 8), first(8, 8), second(8, 8);
  for (size_t i = 0; i < splats.size(); ++i) {
    whole.add(splats[i].x, splats[i].y, splats[i].value);
    (i % 3 == 0 ? first : second).add(splats[i].x, splats[i].y, splats[i].value);
  }
  first.add(second);
  for (const char* c : {"R", "G", "B"}) EXPECT_EQ(whole.toImage().channel(c), first.toImage().channel(c));
}

TEST(SplatFilm, RejectsNonFiniteAndNegativeValuesAndClampsHugeOnes) {
  SplatFilm film(2, 2);
  film.add(0, 0, Rgb(NAN, 1, 1));
  film.add(0, 0, Rgb(INFINITY, 1, 1));
  film.add(0, 0, Rgb(-1, 1, 1));
  film.add(5, 0, Rgb(1, 1, 1));  // outside: ignored
  film.add(1, 1, Rgb(1e30f, 0, 0));
  EXPECT_EQ(film.rejected(), 3u);
  EXPECT_EQ(film.clamped(), 1u);
  EXPECT_TRUE(film.value(0, 0).isBlack());
  EXPECT_EQ(film.value(1, 1).r, static_cast<float>(SplatFilm::kLargestSplat));
  EXPECT_THROW(SplatFilm(0, 3), std::invalid_argument);
}

TEST(SplatFilm, ScaleMultipliesTheSums) {
  SplatFilm film(1, 1);
  film.add(0, 0, Rgb(0.25f, 0.5f, 1.0f));
  const Rgb v = film.value(0, 0, 4.0);
  EXPECT_EQ(v.r, 1.0f);
  EXPECT_EQ(v.g, 2.0f);
  EXPECT_EQ(v.b, 4.0f);
}

}  // namespace
}  // namespace pathfarm
