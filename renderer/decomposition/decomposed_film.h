#pragma once
// The buffers of a decomposed frame (channel names `<component>.<buffer>.<channel>`, see
// docs/decomposition.md) and each pixel's accumulation of its samples into them.
#include <optional>
#include <string>
#include <vector>

#include "image/frame_image.h"
#include "renderer/decomposition/decomposition.h"
#include "renderer/decomposition/path_decomposer.h"

namespace pathfarm {

// What one camera sample adds to its pixel besides its components.
struct SampleExtras {
  bool hit = false;             // the camera ray hit a surface
  int object = -1;              // which object, if it did
  Vec3f position;               // where
  float depth = 0;              // how far
  bool motionSampled = false;   // whether this sample measured the primary motion:
  std::optional<Vec2f> motion, motionBack;  // to the next and from the previous frame
};

class DecomposedFilm {
 public:
  // Motion is measured on the first samples of a pixel only: it varies smoothly inside
  // the pixel, and projecting every sample into three frames would cost more than the
  // rest of the decomposition (an animated camera is re-evaluated for each).
  static constexpr int kMotionSamples = 8;

  // Adds the decomposition's channels (and the frame-wide depth, motion, silhouette and
  // moving caustic: `moving_caustic.Y`, the mean luminance of the samples' moving caustics,
  // path_decomposer.h) to `image`.
  DecomposedFilm(FrameImage& image, const Decomposition& decomposition);

  // One pixel's running sums; lives on the stack of the thread rendering the pixel.
  class Pixel {
   public:
    explicit Pixel(int components);
    void add(const SampleComponents& components, const SampleExtras& extras);
    // A sample traced for features only (RenderSettings::reflectanceSpp): its components'
    // reflectance joins their mean reflectance; nothing else of it is kept.
    void addReflectance(const SampleComponents& components);
    // A specular component's motion from the manifold walk (specular_motion.h), which
    // replaces the samples' primary motion; nothing where the walk found none. Valid only
    // with both directions.
    void setSpecularMotion(int component, std::optional<Vec2f> forward, std::optional<Vec2f> backward);

   private:
    friend class DecomposedFilm;
    struct Component {
      double color[3] = {}, colorSquared[3] = {};
      int features = 0, moving = 0;
      int reflectanceOnly = 0;  // addReflectance's samples with features
      double reflectance[3] = {}, normal[3] = {}, uv[2] = {}, depth = 0, direct[3] = {};
      double motion[2] = {}, motionBack[2] = {};
      uint32_t objectId = 0, primitive = 0;
      bool specular = false;
      std::optional<Vec2f> specularMotion, specularMotionBack;
    };
    std::vector<Component> components_;
    int samples_ = 0, hits_ = 0, moving_ = 0;
    double depth_ = 0, motion_[2] = {}, motionBack_[2] = {}, movingCaustic_ = 0;
    bool silhouette_ = false;
    int firstObject_ = -2;  // -2: no sample yet, -1: the background
    std::optional<Vec2f> firstMotion_;
  };

  void write(size_t pixel, const Pixel& sums) const;

 private:
  struct ComponentChannels {
    float *color[3], *variance[3], *reflectance[3], *irradiance[3], *normal[3], *objectId, *primitive, *uv[2],
        *depth, *coverage, *direct[3], *motion[2], *motionBack[2], *motionValid;
  };
  std::vector<ComponentChannels> components_;
  float *depth_, *motion_[2], *motionBack_[2], *silhouette_, *movingCaustic_;
};

}  // namespace pathfarm
