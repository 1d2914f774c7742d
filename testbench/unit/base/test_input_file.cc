// Every reader opens its input through open_input_file: regular files only (a FIFO, device,
// directory or socket is refused at once, without blocking), the size limit is checked before
// reading, and a file opened as an input is never replaced by an output of the same process.
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "blocks/base/atomic_file.h"
#include "blocks/base/input_error.h"
#include "blocks/base/input_file.h"
#include "blocks/base/output_set.h"
#include "testbench/lib/temp_dir.h"

namespace texsim {
namespace {

std::string error_of(const std::string& path, uint64_t limit = kMaxTextInput) {
  try {
    read_input_file(path, "scene file", limit);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(accepted)";
}

std::string slurp(const std::string& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(InputFile, ReadsARegularFileWhole) {
  TempDir d("input_file");
  std::ofstream(d.file("a.toml"), std::ios::binary) << std::string("x\0y\n", 4);
  EXPECT_EQ(read_input_file(d.file("a.toml"), "scene file", 4), std::string("x\0y\n", 4));
  EXPECT_EQ(check_input_file(d.file("a.toml"), "scene file", 4), 4U);
  std::ofstream(d.file("empty")) << "";
  EXPECT_EQ(read_input_file(d.file("empty"), "scene file", 0), "");
}

TEST(InputFile, SpecialFilesAreRefusedWithoutBlocking) {
  TempDir d("input_file");
  EXPECT_EQ(error_of(d.file("missing.toml")),
            d.file("missing.toml") + ": cannot open scene file: no such file");
  EXPECT_EQ(error_of(d.file("")), d.file("") + ": cannot read scene file: is a directory");
  // A FIFO with no writer: a plain open would block forever.
  ASSERT_EQ(::mkfifo(d.file("fifo").c_str(), 0600), 0);
  EXPECT_EQ(
      error_of(d.file("fifo")),
      d.file("fifo") + ": cannot read scene file: is a FIFO (named pipe), not a regular file");
  // /dev/zero would read until memory runs out.
  EXPECT_EQ(error_of("/dev/zero"),
            "/dev/zero: cannot read scene file: is a device, not a regular file");
  const std::string sock = d.file("s");
  const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
  ASSERT_GE(fd, 0);
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  ASSERT_LT(sock.size(), sizeof addr.sun_path);
  std::memcpy(addr.sun_path, sock.c_str(), sock.size() + 1);
  ASSERT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
  EXPECT_EQ(error_of(sock), sock + ": cannot read scene file: is a socket, not a regular file");
  ::close(fd);
}

TEST(InputFile, SizeLimitIsCheckedBeforeReading) {
  TempDir d("input_file");
  std::ofstream(d.file("big")) << std::string(11, 'a');
  EXPECT_EQ(error_of(d.file("big"), 10),
            d.file("big") + ": scene file is 11 bytes, more than the limit of 10 bytes");
  // A sparse 4 GiB file is refused from its size alone (reading it would take seconds).
  std::filesystem::resize_file(d.file("big"), uint64_t{4} << 30);
  EXPECT_NE(error_of(d.file("big")).find("more than the limit"), std::string::npos);
}

TEST(InputFile, AnOutputNeverReplacesAnInputOfTheProcess) {
  TempDir d("input_file");
  std::ofstream(d.file("report.json")) << "the scene";
  std::ofstream(d.file("other.json")) << "not read";
  read_input_file(d.file("report.json"), "scene file", kMaxTextInput);
  EXPECT_THROW(refuse_overwriting_input(d.file("report.json")), InputError);
  EXPECT_NO_THROW(refuse_overwriting_input(d.file("other.json")));
  EXPECT_NO_THROW(refuse_overwriting_input(d.file("absent.json")));
  // Through a hard link or another spelling of the path, too: files are compared by inode.
  std::filesystem::create_hard_link(d.file("report.json"), d.file("alias.json"));
  EXPECT_THROW(refuse_overwriting_input(d.file("./alias.json")), InputError);

  // The writers refuse it and leave the input and no temporary behind.
  EXPECT_THROW(write_file_atomic(d.file("report.json"), "a report"), InputError);
  EXPECT_EQ(slurp(d.file("report.json")), "the scene");
  {
    OutputSet set(d.file(""));
    write_file_atomic(set.path("image.png"), "image");
    write_file_atomic(set.path("report.json"), "a report");
    EXPECT_THROW(set.commit(), InputError);
  }
  EXPECT_EQ(slurp(d.file("report.json")), "the scene");
  EXPECT_FALSE(std::filesystem::exists(d.file("image.png")));
  EXPECT_EQ(d.entries(), 3U);  // report.json, other.json, alias.json: no staging, no temporary
}

}  // namespace
}  // namespace texsim
