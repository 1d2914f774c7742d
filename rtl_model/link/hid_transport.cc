#include "rtl_model/link/hid_transport.h"

#include <hidapi/hidapi.h>

#include <cstdio>
#include <cwchar>

namespace texsim::link {

namespace {

std::string narrow(const wchar_t* w) {
  std::string s;
  if (!w) return s;
  for (; *w; ++w) s += (*w >= 32 && *w < 127) ? static_cast<char>(*w) : '?';
  return s;
}

std::string vid_pid(uint16_t vid, uint16_t pid) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%04x:%04x", vid, pid);
  return buf;
}

hid_device* dev(void* p) { return static_cast<hid_device*>(p); }

}  // namespace

std::vector<HidDeviceInfo> HidTransport::enumerate(uint16_t vid, uint16_t pid) {
  if (hid_init() != 0) throw LinkError("hidapi could not start: " + narrow(hid_error(nullptr)));
  std::vector<HidDeviceInfo> out;
  hid_device_info* list = hid_enumerate(vid, pid);
  for (const hid_device_info* d = list; d; d = d->next) {
    out.push_back({d->path ? d->path : "", narrow(d->product_string), narrow(d->serial_number)});
  }
  hid_free_enumeration(list);
  return out;
}

HidTransport::HidTransport(uint16_t vid, uint16_t pid) {
  const std::vector<HidDeviceInfo> found = enumerate(vid, pid);
  const std::string id = vid_pid(vid, pid);
  if (found.empty()) {
    throw LinkError("no USB HID device " + id +
                    " found: is the board plugged in and flashed with the link firmware, and "
                    "may this user open its /dev/hidraw node (udev rule in docs/rtl/link.md)?");
  }
  device_ = hid_open_path(found[0].path.c_str());
  if (!device_) {
    throw LinkError("cannot open USB HID device " + id + " at " + found[0].path + ": " +
                    narrow(hid_error(nullptr)) +
                    " (permissions: see the udev rule in docs/rtl/link.md)");
  }
  description_ = "HID device " + id + " " + found[0].path;
}

HidTransport::~HidTransport() {
  if (device_) hid_close(dev(device_));
}

void HidTransport::write(const Report& report) {
  // hidapi's first byte is the report ID: 0, the board's reports are unnumbered.
  std::array<uint8_t, kReportSize + 1> buf{};
  std::copy(report.begin(), report.end(), buf.begin() + 1);
  if (hid_write(dev(device_), buf.data(), buf.size()) < 0) {
    throw LinkError("writing to the " + description_ +
                    " failed: " + narrow(hid_error(dev(device_))));
  }
}

std::vector<uint8_t> HidTransport::read(int timeout_ms) {
  std::vector<uint8_t> buf(kReportSize);
  const int n = hid_read_timeout(dev(device_), buf.data(), buf.size(), timeout_ms);
  if (n < 0) {
    throw LinkError("reading from the " + description_ +
                    " failed: " + narrow(hid_error(dev(device_))));
  }
  buf.resize(static_cast<size_t>(n));
  return buf;
}

}  // namespace texsim::link
