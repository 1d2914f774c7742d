#pragma once
// The link over a USB HID device with hidapi (hidraw backend): enumerate by VID/PID, open the
// first match, 64-byte reports without a report ID. No device, or one that cannot be opened,
// is a LinkError with what to check (docs/rtl/link.md, "Attaching a board"); reads wait at
// most their timeout, so nothing here hangs.
#include <cstdint>
#include <string>
#include <vector>

#include "rtl_model/link/transport.h"

namespace texsim::link {

// pid.codes' VID with a test PID; a board built from docs/rtl/link.md may use its own.
inline constexpr uint16_t kDefaultVid = 0x1209;
inline constexpr uint16_t kDefaultPid = 0x0001;

struct HidDeviceInfo {
  std::string path, product, serial;
};

class HidTransport : public Transport {
 public:
  // Devices with this VID/PID (none: empty).
  static std::vector<HidDeviceInfo> enumerate(uint16_t vid, uint16_t pid);
  // Opens the first device with this VID/PID; throws LinkError if there is none.
  HidTransport(uint16_t vid, uint16_t pid);
  ~HidTransport() override;
  HidTransport(const HidTransport&) = delete;
  HidTransport& operator=(const HidTransport&) = delete;

  void write(const Report& report) override;
  std::vector<uint8_t> read(int timeout_ms) override;
  std::string describe() const override { return description_; }

 private:
  void* device_ = nullptr;  // hid_device*
  std::string description_;
};

}  // namespace texsim::link
