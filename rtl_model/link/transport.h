#pragma once
// What carries the link's 64-byte reports between host and board: a USB HID device
// (HidTransport), an in-process board (VirtualBoard), or a wrapper around either (the fault
// injector of testbench/cosim). LinkHost talks to every one of them through this interface only.
#include <string>
#include <vector>

#include "rtl_model/link/framing.h"

namespace texsim::link {

class Transport {
 public:
  virtual ~Transport() = default;
  // Sends one report; throws LinkError if the device is gone.
  virtual void write(const Report& report) = 0;
  // The next report as received (normally 64 bytes), or an empty vector when none arrives
  // within timeout_ms; throws LinkError if the device is gone.
  virtual std::vector<uint8_t> read(int timeout_ms) = 0;
  // For messages: "virtual board", "HID 1209:0001 /dev/hidraw3".
  virtual std::string describe() const = 0;
};

}  // namespace texsim::link
