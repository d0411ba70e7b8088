#include "postproc/flow/optical_flow.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "image/size_text.h"
#include "postproc/filters/warp.h"

namespace pathfarm {
namespace {

using Plane = std::vector<float>;

template <typename F>
void forRows(int h, F&& body) {
  tbb::parallel_for(tbb::blocked_range<int>(0, h, 8), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y != rows.end(); ++y) body(y);
  });
}

// ---------------------------------------------------------------- validation

void checkPlanes(const Planes& planes, const char* what) {
  if (planes.width <= 0 || planes.height <= 0)
    throw std::invalid_argument(std::string("optical flow: image ") + what + " is empty (" +
                                sizeText(planes.width, planes.height) + ")");
  if (planes.channels.empty())
    throw std::invalid_argument(std::string("optical flow: image ") + what + " has no channels");
  for (size_t c = 0; c < planes.channels.size(); ++c) {
    const Plane& plane = planes.channels[c];
    if (plane.size() != planes.pixelCount())
      throw std::invalid_argument(std::string("optical flow: channel ") + std::to_string(c) + " of image " + what +
                                  " holds " + std::to_string(plane.size()) + " values, not " +
                                  std::to_string(planes.pixelCount()));
    for (size_t p = 0; p < plane.size(); ++p)
      if (!std::isfinite(plane[p]))
        throw std::invalid_argument(std::string("optical flow: image ") + what + " has a non-finite value in channel " +
                                    std::to_string(c) + " at pixel (" + std::to_string(p % planes.width) + ", " +
                                    std::to_string(p / planes.width) + ")");
  }
}

void checkPair(const Planes& a, const Planes& b) {
  checkPlanes(a, "A");
  checkPlanes(b, "B");
  if (a.width != b.width || a.height != b.height)
    throw std::invalid_argument("optical flow: image A is " + sizeText(a.width, a.height) + " but image B is " +
                                sizeText(b.width, b.height));
  if (a.channels.size() != b.channels.size())
    throw std::invalid_argument("optical flow: image A has " + std::to_string(a.channels.size()) +
                                " channels but image B has " + std::to_string(b.channels.size()));
}

void checkFlow(const FlowField& flow, int w, int h, const char* what) {
  if (flow.width != w || flow.height != h)
    throw std::invalid_argument(std::string("optical flow: ") + what + " is " + sizeText(flow.width, flow.height) +
                                ", expected " + sizeText(w, h));
  const size_t n = static_cast<size_t>(w) * static_cast<size_t>(h);
  if (flow.dx.size() != n || flow.dy.size() != n)
    throw std::invalid_argument(std::string("optical flow: ") + what + "'s planes do not hold " + sizeText(w, h) +
                                " values");
  for (size_t p = 0; p < n; ++p)
    if (!std::isfinite(flow.dx[p]) || !std::isfinite(flow.dy[p]))
      throw std::invalid_argument(std::string("optical flow: ") + what + " is not finite at pixel (" +
                                  std::to_string(p % w) + ", " + std::to_string(p / w) + ")");
}

void checkMask(const std::vector<float>* mask, size_t pixels) {
  if (mask == nullptr || mask->empty()) return;
  if (mask->size() != pixels)
    throw std::invalid_argument("optical flow: the occlusion mask holds " + std::to_string(mask->size()) +
                                " values, the images " + std::to_string(pixels));
  for (float m : *mask)
    if (!std::isfinite(m)) throw std::invalid_argument("optical flow: the occlusion mask has a non-finite value");
}

void checkSettings(const FlowSettings& s) {
  auto fail = [](const std::string& text) { throw std::invalid_argument("optical flow settings: " + text); };
  if (!(s.lambda > 0.0f) || !std::isfinite(s.lambda)) fail("lambda must be positive and finite");
  if (!(s.gradientWeight >= 0.0f) || !std::isfinite(s.gradientWeight)) fail("gradientWeight must be >= 0");
  if (!(s.downsample >= 0.5f && s.downsample <= 0.9f)) fail("downsample must be in [0.5, 0.9]");
  if (s.minLevelSize < 1) fail("minLevelSize must be >= 1");
  if (s.maxLevels < 0) fail("maxLevels must be >= 0");
  if (s.warps < 1 || s.fixedPointIterations < 1 || s.sorIterations < 1) fail("iteration counts must be >= 1");
  if (!(s.sorOmega > 0.0f && s.sorOmega < 2.0f)) fail("sorOmega must be in (0, 2)");
  if (!(s.epsilon > 0.0f) || !std::isfinite(s.epsilon)) fail("epsilon must be positive");
  if (!(s.zeta > 0.0f) || !std::isfinite(s.zeta)) fail("zeta must be positive");
  if (!(s.presmoothing >= 0.0f) || !std::isfinite(s.presmoothing)) fail("presmoothing must be >= 0");
}

// ---------------------------------------------------------------- image helpers

// Bilinear lookup at (x, y), clamped to the image.
inline float sample(const Plane& plane, int w, int h, float x, float y) {
  x = std::clamp(x, 0.0f, static_cast<float>(w - 1));
  y = std::clamp(y, 0.0f, static_cast<float>(h - 1));
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const int x1 = std::min(x0 + 1, w - 1), y1 = std::min(y0 + 1, h - 1);
  const float fx = x - static_cast<float>(x0), fy = y - static_cast<float>(y0);
  const size_t W = static_cast<size_t>(w);
  const float top = plane[static_cast<size_t>(y0) * W + static_cast<size_t>(x0)] * (1.0f - fx) +
                    (fx != 0.0f ? plane[static_cast<size_t>(y0) * W + static_cast<size_t>(x1)] * fx : 0.0f);
  if (fy == 0.0f) return top;
  const float bottom = plane[static_cast<size_t>(y1) * W + static_cast<size_t>(x0)] * (1.0f - fx) +
                       (fx != 0.0f ? plane[static_cast<size_t>(y1) * W + static_cast<size_t>(x1)] * fx : 0.0f);
  return top * (1.0f - fy) + bottom * fy;
}

// Separable Gaussian blur with edge clamping.
Plane gaussianBlur(const Plane& in, int w, int h, float sigma) {
  if (sigma <= 0.01f) return in;
  const int radius = std::max(1, static_cast<int>(std::ceil(3.0f * sigma)));
  std::vector<float> kernel(static_cast<size_t>(2 * radius + 1));
  float sum = 0.0f;
  for (int i = -radius; i <= radius; ++i) {
    const float v = std::exp(-0.5f * static_cast<float>(i * i) / (sigma * sigma));
    kernel[static_cast<size_t>(i + radius)] = v;
    sum += v;
  }
  for (float& v : kernel) v /= sum;
  const size_t W = static_cast<size_t>(w);
  Plane tmp(in.size()), out(in.size());
  forRows(h, [&](int y) {
    const float* row = &in[static_cast<size_t>(y) * W];
    for (int x = 0; x < w; ++x) {
      float acc = 0.0f;
      for (int i = -radius; i <= radius; ++i)
        acc += kernel[static_cast<size_t>(i + radius)] * row[std::clamp(x + i, 0, w - 1)];
      tmp[static_cast<size_t>(y) * W + static_cast<size_t>(x)] = acc;
    }
  });
  forRows(h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      float acc = 0.0f;
      for (int i = -radius; i <= radius; ++i)
        acc += kernel[static_cast<size_t>(i + radius)] *
               tmp[static_cast<size_t>(std::clamp(y + i, 0, h - 1)) * W + static_cast<size_t>(x)];
      out[static_cast<size_t>(y) * W + static_cast<size_t>(x)] = acc;
    }
  });
  return out;
}

// Bilinear resampling of a (pre-blurred) plane to nw x nh, aligning pixel footprints.
Plane resample(const Plane& in, int w, int h, int nw, int nh) {
  Plane out(static_cast<size_t>(nw) * static_cast<size_t>(nh));
  const float sx = static_cast<float>(w) / static_cast<float>(nw), sy = static_cast<float>(h) / static_cast<float>(nh);
  forRows(nh, [&](int y) {
    const float fy = (static_cast<float>(y) + 0.5f) * sy - 0.5f;
    for (int x = 0; x < nw; ++x) {
      const float fx = (static_cast<float>(x) + 0.5f) * sx - 0.5f;
      out[static_cast<size_t>(y) * static_cast<size_t>(nw) + static_cast<size_t>(x)] = sample(in, w, h, fx, fy);
    }
  });
  return out;
}

// 5-point central derivative (1, -8, 0, 8, -1) / 12 along x or y, edge-clamped.
Plane derivative(const Plane& in, int w, int h, bool alongX) {
  Plane out(in.size());
  const size_t W = static_cast<size_t>(w);
  forRows(h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      auto at = [&](int d) {
        const int xx = alongX ? std::clamp(x + d, 0, w - 1) : x;
        const int yy = alongX ? y : std::clamp(y + d, 0, h - 1);
        return in[static_cast<size_t>(yy) * W + static_cast<size_t>(xx)];
      };
      out[static_cast<size_t>(y) * W + static_cast<size_t>(x)] = (at(-2) - 8.0f * at(-1) + 8.0f * at(1) - at(2)) / 12.0f;
    }
  });
  return out;
}

// ---------------------------------------------------------------- the solver

// One image of a pyramid level with the derivatives the data terms need.
struct LevelImage {
  std::vector<Plane> value, dx, dy, dxx, dxy, dyy;  // per channel; second derivatives only with gradient constancy
};

LevelImage prepare(const std::vector<Plane>& channels, int w, int h, bool second) {
  LevelImage img;
  img.value = channels;
  for (const Plane& c : channels) {
    img.dx.push_back(derivative(c, w, h, true));
    img.dy.push_back(derivative(c, w, h, false));
    if (second) {
      img.dxx.push_back(derivative(img.dx.back(), w, h, true));
      img.dxy.push_back(derivative(img.dx.back(), w, h, false));
      img.dyy.push_back(derivative(img.dy.back(), w, h, false));
    }
  }
  return img;
}

// The symmetric 3x3 motion tensor (u, v, 1) J (u, v, 1)^T of one pixel.
struct Tensor {
  float j11 = 0, j12 = 0, j13 = 0, j22 = 0, j23 = 0, j33 = 0;
  void add(float weight, float gx, float gy, float gz) {
    j11 += weight * gx * gx;
    j12 += weight * gx * gy;
    j13 += weight * gx * gz;
    j22 += weight * gy * gy;
    j23 += weight * gy * gz;
    j33 += weight * gz * gz;
  }
  float energy(float du, float dv) const {
    return j11 * du * du + 2.0f * j12 * du * dv + 2.0f * j13 * du + j22 * dv * dv + 2.0f * j23 * dv + j33;
  }
};

// The flow of one pyramid level of size w x h, refined warp by warp (Brox et al.'s outer
// fixed point): each warp linearizes the data terms about the current flow and solves for
// an increment (du, dv), with Psi' lagged (the inner fixed point) and every linear system
// solved by red-black SOR.
class LevelSolver {
 public:
  LevelSolver(const LevelImage& A, const LevelImage& B, const Plane& mask, int w, int h, const FlowSettings& s,
              Plane& u, Plane& v)
      : A_(A), B_(B), mask_(mask), w_(w), h_(h), s_(s), u_(u), v_(v) {}

  void solve() {
    for (int warp = 0; warp < s_.warps; ++warp) {
      linearize();
      for (int fixedPoint = 0; fixedPoint < s_.fixedPointIterations; ++fixedPoint) {
        lagNonlinearity();
        weighSmoothness();
        for (int sweep = 0; sweep < s_.sorIterations; ++sweep)
          for (int colour = 0; colour < 2; ++colour) relax(colour);
      }
      for (size_t p = 0; p < n_; ++p) {
        u_[p] += du_[p];
        v_[p] += dv_[p];
      }
    }
  }

 private:
  // Linearize about the current flow: B and its derivatives looked up at p + w(p), the data
  // terms' motion tensors, and a zero increment.
  void linearize() {
    forRows(h_, [&](int y) {
      for (int x = 0; x < w_; ++x) {
        const size_t p = static_cast<size_t>(y) * W_ + static_cast<size_t>(x);
        const float qx = static_cast<float>(x) + u_[p], qy = static_cast<float>(y) + v_[p];
        const bool inside = qx >= -0.5f && qx < static_cast<float>(w_) - 0.5f && qy >= -0.5f &&
                            qy < static_cast<float>(h_) - 0.5f;
        dataOn_[p] = inside ? std::clamp(1.0f - mask_[p], 0.0f, 1.0f) : 0.0f;
        motionTensors(p, qx, qy);
        du_[p] = 0.0f;
        dv_[p] = 0.0f;
      }
    });
  }

  // The normalized brightness and gradient constancy tensors of pixel p, B read at (qx, qy).
  void motionTensors(size_t p, float qx, float qy) {
    Tensor t;
    Tensor g;
    for (size_t c = 0; c < C_; ++c) {
      const float ix = 0.5f * (A_.dx[c][p] + sample(B_.dx[c], w_, h_, qx, qy));
      const float iy = 0.5f * (A_.dy[c][p] + sample(B_.dy[c], w_, h_, qx, qy));
      const float iz = sample(B_.value[c], w_, h_, qx, qy) - A_.value[c][p];
      t.add(invC_ / (ix * ix + iy * iy + zeta2_), ix, iy, iz);
      if (gradient_) {
        const float ixx = 0.5f * (A_.dxx[c][p] + sample(B_.dxx[c], w_, h_, qx, qy));
        const float ixy = 0.5f * (A_.dxy[c][p] + sample(B_.dxy[c], w_, h_, qx, qy));
        const float iyy = 0.5f * (A_.dyy[c][p] + sample(B_.dyy[c], w_, h_, qx, qy));
        const float ixz = sample(B_.dx[c], w_, h_, qx, qy) - A_.dx[c][p];
        const float iyz = sample(B_.dy[c], w_, h_, qx, qy) - A_.dy[c][p];
        g.add(invC_ / (ixx * ixx + ixy * ixy + zeta2_), ixx, ixy, ixz);
        g.add(invC_ / (ixy * ixy + iyy * iyy + zeta2_), ixy, iyy, iyz);
      }
    }
    brightness_[p] = t;
    if (gradient_) gradientTensor_[p] = g;
  }

  // Lagged nonlinearity: Psi' of the data terms and of the smoothness term.
  void lagNonlinearity() {
    forRows(h_, [&](int y) {
      const int ym = std::max(y - 1, 0), yp = std::min(y + 1, h_ - 1);
      for (int x = 0; x < w_; ++x) {
        const size_t p = static_cast<size_t>(y) * W_ + static_cast<size_t>(x);
        const int xm = std::max(x - 1, 0), xp = std::min(x + 1, w_ - 1);
        auto full = [&](const Plane& f, const Plane& d, int xx, int yy) {
          const size_t q = static_cast<size_t>(yy) * W_ + static_cast<size_t>(xx);
          return f[q] + d[q];
        };
        const float ux = 0.5f * (full(u_, du_, xp, y) - full(u_, du_, xm, y));
        const float uy = 0.5f * (full(u_, du_, x, yp) - full(u_, du_, x, ym));
        const float vx = 0.5f * (full(v_, dv_, xp, y) - full(v_, dv_, xm, y));
        const float vy = 0.5f * (full(v_, dv_, x, yp) - full(v_, dv_, x, ym));
        psiS_[p] = 1.0f / std::sqrt(ux * ux + uy * uy + vx * vx + vy * vy + eps2_);
        lagDataTerms(p);
      }
    });
  }

  // Pixel p's data terms in the linear system: their tensors weighed by Psi'.
  void lagDataTerms(size_t p) {
    float d11 = 0, d12 = 0, d22 = 0, b1 = 0, b2 = 0;
    if (dataOn_[p] > 0.0f) {
      const Tensor& t = brightness_[p];
      const float psiB = dataOn_[p] / std::sqrt(std::max(t.energy(du_[p], dv_[p]), 0.0f) + eps2_);
      d11 = psiB * t.j11;
      d12 = psiB * t.j12;
      d22 = psiB * t.j22;
      b1 = psiB * t.j13;
      b2 = psiB * t.j23;
      if (gradient_) {
        const Tensor& g = gradientTensor_[p];
        const float psiG =
            s_.gradientWeight * dataOn_[p] / std::sqrt(std::max(g.energy(du_[p], dv_[p]), 0.0f) + eps2_);
        d11 += psiG * g.j11;
        d12 += psiG * g.j12;
        d22 += psiG * g.j22;
        b1 += psiG * g.j13;
        b2 += psiG * g.j23;
      }
    }
    diagU_[p] = d11;
    diagV_[p] = d22;
    offD_[p] = d12;
    rhsU_[p] = b1;
    rhsV_[p] = b2;
  }

  // Smoothness weights between neighbours: lambda times the mean of their Psi'.
  void weighSmoothness() {
    forRows(h_, [&](int y) {
      for (int x = 0; x < w_; ++x) {
        const size_t p = static_cast<size_t>(y) * W_ + static_cast<size_t>(x);
        wRight_[p] = x + 1 < w_ ? 0.5f * s_.lambda * (psiS_[p] + psiS_[p + 1]) : 0.0f;
        wDown_[p] = y + 1 < h_ ? 0.5f * s_.lambda * (psiS_[p] + psiS_[p + W_]) : 0.0f;
      }
    });
  }

  // Red-black SOR on the linear system for (du, dv): one sweep over the pixels of one colour.
  void relax(int colour) {
    const float omega = s_.sorOmega;
    forRows(h_, [&](int y) {
      for (int x = (y + colour) & 1; x < w_; x += 2) {
        const size_t p = static_cast<size_t>(y) * W_ + static_cast<size_t>(x);
        float sumW = 0.0f, sumU = 0.0f, sumV = 0.0f;
        auto neighbour = [&](size_t q, float weight) {
          sumW += weight;
          sumU += weight * (u_[q] + du_[q]);
          sumV += weight * (v_[q] + dv_[q]);
        };
        if (x > 0) neighbour(p - 1, wRight_[p - 1]);
        if (x + 1 < w_) neighbour(p + 1, wRight_[p]);
        if (y > 0) neighbour(p - W_, wDown_[p - W_]);
        if (y + 1 < h_) neighbour(p + W_, wDown_[p]);
        const float smoothU = sumU - sumW * u_[p], smoothV = sumV - sumW * v_[p];
        // A 1x1 image with no data has no equation at all: its flow stays as it is.
        if (diagU_[p] + sumW > 0.0f) {
          const float newU = (smoothU - rhsU_[p] - offD_[p] * dv_[p]) / (diagU_[p] + sumW);
          du_[p] += omega * (newU - du_[p]);
        }
        if (diagV_[p] + sumW > 0.0f) {
          const float newV = (smoothV - rhsV_[p] - offD_[p] * du_[p]) / (diagV_[p] + sumW);
          dv_[p] += omega * (newV - dv_[p]);
        }
      }
    });
  }

  const LevelImage& A_;
  const LevelImage& B_;
  const Plane& mask_;
  const int w_, h_;
  const FlowSettings& s_;
  Plane& u_;
  Plane& v_;
  const size_t n_ = static_cast<size_t>(w_) * static_cast<size_t>(h_);
  const size_t W_ = static_cast<size_t>(w_);
  const size_t C_ = A_.value.size();
  const bool gradient_ = s_.gradientWeight > 0.0f;
  const float zeta2_ = s_.zeta * s_.zeta, eps2_ = s_.epsilon * s_.epsilon;
  const float invC_ = 1.0f / static_cast<float>(C_);
  // The data terms linearized about the current flow.
  std::vector<Tensor> brightness_ = std::vector<Tensor>(n_), gradientTensor_ = std::vector<Tensor>(gradient_ ? n_ : 0);
  Plane dataOn_ = Plane(n_);
  // The increment, Psi' of the smoothness term and the linear system's coefficients.
  Plane du_ = Plane(n_), dv_ = Plane(n_), psiS_ = Plane(n_), wRight_ = Plane(n_), wDown_ = Plane(n_);
  Plane diagU_ = Plane(n_), diagV_ = Plane(n_), offD_ = Plane(n_), rhsU_ = Plane(n_), rhsV_ = Plane(n_);
};

struct Level {
  int w, h;
  std::vector<Plane> a, b;
  Plane mask;
};

FlowField solve(const Planes& a, const Planes& b, const FlowSettings& s, const std::vector<float>* occlusionMask) {
  const int w0 = a.width, h0 = a.height;
  const size_t n0 = a.pixelCount();
  auto preprocess = [&](const Planes& img) {
    std::vector<Plane> out;
    for (const Plane& c : img.channels) {
      Plane p = c;
      if (s.logDomain)
        for (float& value : p) value = std::log(std::max(value, 1e-4f));
      out.push_back(gaussianBlur(p, w0, h0, s.presmoothing));
    }
    return out;
  };
  std::vector<Level> levels;
  levels.push_back(Level{w0, h0, preprocess(a), preprocess(b),
                         occlusionMask != nullptr && !occlusionMask->empty() ? *occlusionMask : Plane(n0, 0.0f)});
  const float sigma = 0.6f * std::sqrt(1.0f / (s.downsample * s.downsample) - 1.0f);
  while (s.maxLevels == 0 || levels.size() < static_cast<size_t>(s.maxLevels)) {
    const Level& fine = levels.back();
    const int nw = static_cast<int>(std::lround(static_cast<float>(fine.w) * s.downsample));
    const int nh = static_cast<int>(std::lround(static_cast<float>(fine.h) * s.downsample));
    if (std::min(nw, nh) < s.minLevelSize || nw < 2 || nh < 2 || nw == fine.w || nh == fine.h) break;
    Level coarse{nw, nh, {}, {}, {}};
    for (const Plane& c : fine.a) coarse.a.push_back(resample(gaussianBlur(c, fine.w, fine.h, sigma), fine.w, fine.h, nw, nh));
    for (const Plane& c : fine.b) coarse.b.push_back(resample(gaussianBlur(c, fine.w, fine.h, sigma), fine.w, fine.h, nw, nh));
    coarse.mask = resample(gaussianBlur(fine.mask, fine.w, fine.h, sigma), fine.w, fine.h, nw, nh);
    levels.push_back(std::move(coarse));
  }

  const bool second = s.gradientWeight > 0.0f;
  Plane u, v;
  for (size_t k = levels.size(); k-- > 0;) {
    const Level& level = levels[k];
    const size_t n = static_cast<size_t>(level.w) * static_cast<size_t>(level.h);
    if (k + 1 == levels.size()) {
      u.assign(n, 0.0f);
      v.assign(n, 0.0f);
    } else {
      const Level& coarse = levels[k + 1];
      const float scaleX = static_cast<float>(level.w) / static_cast<float>(coarse.w);
      const float scaleY = static_cast<float>(level.h) / static_cast<float>(coarse.h);
      Plane nu = resample(u, coarse.w, coarse.h, level.w, level.h);
      Plane nv = resample(v, coarse.w, coarse.h, level.w, level.h);
      for (float& x : nu) x *= scaleX;
      for (float& y : nv) y *= scaleY;
      u = std::move(nu);
      v = std::move(nv);
    }
    const LevelImage A = prepare(level.a, level.w, level.h, second);
    const LevelImage B = prepare(level.b, level.w, level.h, second);
    LevelSolver(A, B, level.mask, level.w, level.h, s, u, v).solve();
  }
  FlowField flow;
  flow.width = w0;
  flow.height = h0;
  flow.dx = std::move(u);
  flow.dy = std::move(v);
  return flow;
}

}  // namespace

FlowField computeFlow(const Planes& a, const Planes& b, const FlowSettings& settings,
                      const std::vector<float>* occlusionMask) {
  checkSettings(settings);
  checkPair(a, b);
  checkMask(occlusionMask, a.pixelCount());
  return solve(a, b, settings, occlusionMask);
}

FlowField bootstrappedFlow(const Planes& a, const Planes& b, const FlowField& primaryMotion,
                           const FlowSettings& settings, const std::vector<float>* occlusionMask, FlowRows rows) {
  checkSettings(settings);
  const bool band = rows.frameHeight > 0;
  if (!band) {
    if (rows.top != 0 || rows.neighbourTop != 0)
      throw std::invalid_argument("optical flow: rows placed in a frame of unknown height");
    checkPair(a, b);
  } else {
    checkPlanes(a, "A");
    if (rows.top < 0 || rows.top + a.height > rows.frameHeight)
      throw std::invalid_argument("optical flow: A's rows " + std::to_string(rows.top) + " to " +
                                  std::to_string(rows.top + a.height) + " are not rows of a frame " +
                                  std::to_string(rows.frameHeight) + " rows tall");
    if (b.height > 0) checkPlanes(b, "B");
    if (b.width != a.width || b.channels.size() != a.channels.size())
      throw std::invalid_argument("optical flow: image B's rows are " + std::to_string(b.width) + " wide with " +
                                  std::to_string(b.channels.size()) + " channels, image A " +
                                  std::to_string(a.width) + " wide with " + std::to_string(a.channels.size()));
  }
  checkFlow(primaryMotion, a.width, a.height, "the primary motion");
  checkMask(occlusionMask, a.pixelCount());
  MotionField motion;
  motion.width = a.width;
  motion.height = a.height;
  motion.x = primaryMotion.dx;
  motion.y = primaryMotion.dy;
  motion.top = rows.top;
  motion.frameHeight = rows.frameHeight;
  if (band) {
    // B must hold the rows the warp reads, inside its frame: else lookups would clamp.
    const auto [sourceFirst, sourceEnd] = warpSourceRows(motion);
    const int heldEnd = rows.neighbourTop + b.height;
    if (rows.neighbourTop < 0 || heldEnd > rows.frameHeight ||
        (sourceFirst < sourceEnd && (sourceFirst < rows.neighbourTop || sourceEnd > heldEnd)))
      throw std::invalid_argument("optical flow: image B holds rows " + std::to_string(rows.neighbourTop) + " to " +
                                  std::to_string(heldEnd) + " of a frame " + std::to_string(rows.frameHeight) +
                                  " rows tall; the primary motion reads rows " + std::to_string(sourceFirst) +
                                  " to " + std::to_string(sourceEnd));
  }
  const std::vector<float> inside = warpValidity(motion);
  Planes warped = a;
  if (std::find(inside.begin(), inside.end(), 1.0f) != inside.end()) {
    if (b.height <= 0) throw std::invalid_argument("optical flow: image B holds no rows, but the primary motion leads into it");
    const Planes fromB = warpPlanes(b, motion, WarpLookup::Bilinear, rows.neighbourTop);
    for (size_t c = 0; c < warped.channels.size(); ++c)
      for (size_t p = 0; p < inside.size(); ++p)
        if (inside[p] == 1.0f) warped.channels[c][p] = fromB.channels[c][p];
  }
  std::vector<float> mask(inside.size());
  for (size_t p = 0; p < mask.size(); ++p) {
    mask[p] = 1.0f - inside[p];
    if (occlusionMask != nullptr && !occlusionMask->empty()) mask[p] = std::max(mask[p], (*occlusionMask)[p]);
  }
  const FlowField residual = solve(a, warped, settings, &mask);
  FlowField out(a.width, a.height);
  const int w = a.width, h = a.height;
  const size_t W = static_cast<size_t>(w);
  forRows(h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const size_t p = static_cast<size_t>(y) * W + static_cast<size_t>(x);
      const float qx = static_cast<float>(x) + residual.dx[p], qy = static_cast<float>(y) + residual.dy[p];
      out.dx[p] = residual.dx[p] + sample(primaryMotion.dx, w, h, qx, qy);
      out.dy[p] = residual.dy[p] + sample(primaryMotion.dy, w, h, qx, qy);
    }
  });
  return out;
}

OcclusionResult forwardBackward(const FlowField& forward, const FlowField& backward, float threshold) {
  if (forward.width <= 0 || forward.height <= 0)
    throw std::invalid_argument("forward-backward check: the forward flow is empty");
  if (!(threshold >= 0.0f) || !std::isfinite(threshold))
    throw std::invalid_argument("forward-backward check: the threshold must be finite and >= 0");
  checkFlow(forward, forward.width, forward.height, "the forward flow");
  checkFlow(backward, forward.width, forward.height, "the backward flow");
  const int w = forward.width, h = forward.height;
  const size_t W = static_cast<size_t>(w);
  OcclusionResult result;
  result.width = w;
  result.height = h;
  result.mask.assign(forward.pixelCount(), 0.0f);
  const float t2 = threshold * threshold;
  forRows(h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const size_t p = static_cast<size_t>(y) * W + static_cast<size_t>(x);
      const float qx = static_cast<float>(x) + forward.dx[p], qy = static_cast<float>(y) + forward.dy[p];
      const bool inside = qx >= -0.5f && qx < static_cast<float>(w) - 0.5f && qy >= -0.5f &&
                          qy < static_cast<float>(h) - 0.5f;
      bool occluded = !inside;
      if (inside) {
        const float ex = forward.dx[p] + sample(backward.dx, w, h, qx, qy);
        const float ey = forward.dy[p] + sample(backward.dy, w, h, qx, qy);
        occluded = ex * ex + ey * ey > t2;
      }
      result.mask[p] = occluded ? 1.0f : 0.0f;
    }
  });
  for (float m : result.mask) result.count += m != 0.0f ? 1 : 0;
  return result;
}

FlowField flowWithOcclusions(const Planes& a, const Planes& b, const FlowSettings& settings, OcclusionResult* occlusion,
                             float threshold) {
  checkSettings(settings);
  checkPair(a, b);
  if (!(threshold >= 0.0f) || !std::isfinite(threshold))
    throw std::invalid_argument("flowWithOcclusions: the threshold must be finite and >= 0");
  const FlowField forward = solve(a, b, settings, nullptr);
  const FlowField backward = solve(b, a, settings, nullptr);
  OcclusionResult result = forwardBackward(forward, backward, threshold);
  FlowField flow = solve(a, b, settings, &result.mask);
  if (occlusion != nullptr) *occlusion = std::move(result);
  return flow;
}

}  // namespace pathfarm
