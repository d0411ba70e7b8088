#pragma once
// An Embree device that reports its errors as exceptions instead of silently.
#include <embree3/rtcore.h>

#include <string>

namespace pathfarm {

class EmbreeDevice {
 public:
  EmbreeDevice();
  ~EmbreeDevice();
  EmbreeDevice(const EmbreeDevice&) = delete;
  EmbreeDevice& operator=(const EmbreeDevice&) = delete;

  RTCDevice get() const { return device_; }
  // Throws std::runtime_error with Embree's message if the last calls failed.
  void check(const char* what) const;

 private:
  RTCDevice device_;
};

}  // namespace pathfarm
