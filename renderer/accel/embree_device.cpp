#include "renderer/accel/embree_device.h"

#include <spdlog/spdlog.h>

#include <stdexcept>

namespace pathfarm {
namespace {

void logEmbreeError(void*, RTCError code, const char* message) {
  spdlog::error("Embree error {}: {}", static_cast<int>(code), message ? message : "");
}

}  // namespace

EmbreeDevice::EmbreeDevice() : device_(rtcNewDevice(nullptr)) {
  if (!device_) throw std::runtime_error("cannot create an Embree device");
  rtcSetDeviceErrorFunction(device_, logEmbreeError, nullptr);
}

EmbreeDevice::~EmbreeDevice() { rtcReleaseDevice(device_); }

void EmbreeDevice::check(const char* what) const {
  const RTCError error = rtcGetDeviceError(device_);
  if (error != RTC_ERROR_NONE)
    throw std::runtime_error(std::string("Embree failed while ") + what + " (error " +
                             std::to_string(static_cast<int>(error)) + ")");
}

}  // namespace pathfarm
