// libFuzzer harness: the apitrace importer (pipeline/capture/apitrace_import.h) on arbitrary
// dump text. The input is also written as the blobs of calls 1 to 4 (blob_call1.bin ..
// blob_call4.bin), so mutated pointer, index and pixel arguments reach the array readers.
#include <unistd.h>

#include <filesystem>
#include <string>

#include "pipeline/capture/apitrace_import.h"
#include "testbench/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string dir = [] {
    std::string d = "/tmp/texsim-fuzz-dump-" + std::to_string(static_cast<long>(::getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  const std::string dump = texsim::fuzz::write_input(data, size, ".dump");
  for (int call = 1; call <= 4; ++call) {
    const std::string blob = texsim::fuzz::write_input(data, size, ".blob");
    std::filesystem::rename(blob, dir + "/blob_call" + std::to_string(call) + ".bin");
  }
  texsim::fuzz::expect_clean(
      [&] { texsim::import_apitrace_dump(dump, dir, 0, 1, dir + "/out.draws", "fuzz.trace"); });
  return 0;
}
