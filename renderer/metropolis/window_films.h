#pragma once
// One SplatFilm per frame of a window: a chain's splats land in the frame their time
// falls in, from any thread, with bits that do not depend on the order.
#include <memory>
#include <vector>

#include "renderer/film/splat_film.h"
#include "renderer/metropolis/chain_target.h"
#include "renderer/metropolis/window_time.h"

namespace pathfarm {

class WindowFilms {
 public:
  WindowFilms(FrameWindow window, int width, int height);

  // Adds weight * value / scalar at the contribution's pixel and frame (the expected-value
  // splat of a Metropolis step); contributions of no scalar weight land nowhere.
  void splat(const Contribution& contribution, double weight);
  // Each frame's sums times `scale`, in frame order.
  std::vector<FrameImage> toImages(double scale) const;
  uint64_t rejected() const;

 private:
  FrameWindow window_;
  std::vector<std::unique_ptr<SplatFilm>> films_;
};

}  // namespace pathfarm
