#include "renderer/metropolis/window_films.h"

#include <cmath>

namespace pathfarm {

WindowFilms::WindowFilms(FrameWindow window, int width, int height) : window_(window) {
  for (int f = 0; f < window.count; ++f) films_.push_back(std::make_unique<SplatFilm>(width, height));
}

void WindowFilms::splat(const Contribution& contribution, double weight) {
  const double scalar = contribution.scalar();
  if (weight <= 0 || scalar <= 0) return;
  if (contribution.frame < window_.first || contribution.frame >= window_.end()) return;
  const double w = weight / scalar;
  const Rgb& v = contribution.value;
  films_[static_cast<size_t>(contribution.frame - window_.first)]->add(
      static_cast<int>(std::floor(contribution.film.x)), static_cast<int>(std::floor(contribution.film.y)),
      Rgb(static_cast<float>(v.r * w), static_cast<float>(v.g * w), static_cast<float>(v.b * w)));
}

std::vector<FrameImage> WindowFilms::toImages(double scale) const {
  std::vector<FrameImage> images;
  for (const auto& film : films_) images.push_back(film->toImage(scale));
  return images;
}

uint64_t WindowFilms::rejected() const {
  uint64_t total = 0;
  for (const auto& film : films_) total += film->rejected();
  return total;
}

}  // namespace pathfarm
