#include "pipeline/image_io/astcenc_encoder.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "blocks/base/atomic_file.h"
#include "blocks/base/input_error.h"
#include "blocks/base/temp_registry.h"
#include "pipeline/image_io/astc_file.h"
#include "pipeline/image_io/png_file.h"

namespace texsim {

namespace {

constexpr int kMaxSide = 16384;

const char* preset_flag(AstcPreset p) {
  switch (p) {
    case AstcPreset::Fastest:
      return "-fastest";
    case AstcPreset::Fast:
      return "-fast";
    case AstcPreset::Medium:
      return "-medium";
    case AstcPreset::Thorough:
      return "-thorough";
  }
  return "-medium";
}

// Scratch files removed when the encoder returns or throws.
struct ScratchFiles {
  std::vector<std::string> paths;
  ~ScratchFiles() {
    for (const std::string& p : paths) remove_temp(p);
  }
};

// Runs `argv[0]` with its standard output and error in `log`; its exit status, or -1 with
// `why` when it could not be started or did not exit normally.
int run(const std::vector<std::string>& args, const std::string& log, std::string* why) {
  std::vector<char*> argv;
  argv.reserve(args.size() + 1);
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&fa, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                   0600);
  posix_spawn_file_actions_adddup2(&fa, STDOUT_FILENO, STDERR_FILENO);
  pid_t pid = 0;
  const int rc = ::posix_spawn(&pid, argv[0], &fa, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) {
    *why = std::string("cannot start it: ") + std::strerror(rc);
    return -1;
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  *why = WIFSIGNALED(status) ? "killed by signal " + std::to_string(WTERMSIG(status))
                             : std::string("did not exit normally");
  return -1;
}

// The last few lines of a log, on one line, for an error message.
std::string log_tail(const std::string& log) {
  std::ifstream in(log);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) lines.push_back(line);
  std::string s;
  for (size_t i = lines.size() > 3 ? lines.size() - 3 : 0; i < lines.size(); ++i)
    s += (s.empty() ? "" : " | ") + lines[i];
  return s.empty() ? "(it printed nothing)" : s;
}

std::string first_line(const std::string& log) {
  std::ifstream in(log);
  std::string line;
  std::getline(in, line);
  return line;
}

// A unique scratch base in the temporary directory, absolute (so no argument starts with '-').
std::string scratch_base() {
  static std::atomic<unsigned> counter{0};
  std::error_code ec;
  std::filesystem::path dir = std::filesystem::temp_directory_path(ec);
  if (ec) dir = "/tmp";
  dir = std::filesystem::absolute(dir, ec);
  return (dir / ("texsim-astcenc-" + std::to_string(counter.fetch_add(1)))).string();
}

}  // namespace

const char* astc_preset_name(AstcPreset p) { return preset_flag(p) + 1; }

EncodedLevel astcenc_encode(const Rgba8Image& img, const AstcencOptions& o) {
  const std::string& bin = o.binary;
  check_encoder_input(img, bin, kMaxSide);
  if (!is_astc_2d_footprint(o.block_w, o.block_h))
    throw InputError(bin, "block size " + std::to_string(o.block_w) + "x" +
                              std::to_string(o.block_h) + " is not an ASTC 2-D footprint");
  if (o.threads < 1) throw InputError(bin, "thread count must be at least 1");
  if (::access(bin.c_str(), X_OK) != 0)
    throw InputError(bin, std::string("astcenc is not available (") + std::strerror(errno) +
                              "): install Debian's astcenc package (scripts/setup-debian.sh)");
  const Rgba8Image padded = padded_to_blocks(img, o.block_w, o.block_h);
  const std::string base = scratch_base();
  ScratchFiles scratch;
  const std::string png = scratch_path_for(base, ".png");
  const std::string astc = scratch_path_for(base, ".astc");
  const std::string log = scratch_path_for(base, ".log");
  scratch.paths = {png, astc, log};
  const std::string err = write_png_rgba8(png, padded.width, padded.height, padded.rgba.data());
  if (!err.empty()) throw InputError(png, "cannot write the encoder's input: " + err);

  std::string why;
  if (run({bin, "-version"}, log, &why) != 0)
    throw InputError(bin, "`astcenc -version` failed: " + (why.empty() ? log_tail(log) : why));
  const std::string version = first_line(log);
  const std::string block = std::to_string(o.block_w) + "x" + std::to_string(o.block_h);
  const std::vector<std::string> args = {
      bin,  o.srgb ? "-cs" : "-cl",    png,      astc, block, preset_flag(o.preset),
      "-j", std::to_string(o.threads), "-silent"};
  const int status = run(args, log, &why);
  if (status != 0)
    throw InputError(
        bin, (status < 0 ? why : "exit status " + std::to_string(status)) + ": " + log_tail(log));
  std::error_code ec;
  if (!std::filesystem::is_regular_file(astc, ec))
    throw InputError(bin, "exit status 0 but no .astc file written: " + log_tail(log));
  const CompressedImage got = read_astc_file(astc);
  if (got.block_w != o.block_w || got.block_h != o.block_h ||
      got.width != static_cast<uint32_t>(padded.width) ||
      got.height != static_cast<uint32_t>(padded.height))
    throw InputError(
        astc, "astcenc wrote " + got.format_label() + " of " + std::to_string(got.width) + " x " +
                  std::to_string(got.height) + ", not the " + block + " blocks of the " +
                  std::to_string(padded.width) + " x " + std::to_string(padded.height) + " input");
  EncodedLevel out;
  out.format = FileBlockFormat::Astc;
  out.width = img.width;
  out.height = img.height;
  out.block_w = o.block_w;
  out.block_h = o.block_h;
  out.bytes = got.levels[0].bytes;
  std::ostringstream prov;
  prov << version << " (" << (o.srgb ? "-cs" : "-cl") << " " << block << " "
       << preset_flag(o.preset) << " -j " << o.threads << ")";
  out.provenance = prov.str();
  return out;
}

}  // namespace texsim
