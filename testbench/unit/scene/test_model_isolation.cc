// Assimp in a child process (isolated_child.h, model_stream.h): the input on which Assimp
// crashes (testbench/fuzz/known-crashes) ends in an error naming the file; the shipped models
// and a textured OBJ load exactly as in-process; a child that is killed, exits non-zero, hangs,
// over-allocates or sends bad bytes is an error, never a crash or a hang (nor the removal of the
// parent's temporary files); and the stream's reader refuses every malformed count, index and
// number.
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <new>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "blocks/base/input_file.h"
#include "blocks/base/temp_registry.h"
#include "pipeline/scene/isolated_child.h"
#include "pipeline/scene/model_loader.h"
#include "pipeline/scene/model_stream.h"
#include "testbench/lib/error_of.h"
#include "testbench/lib/temp_dir.h"

namespace texsim {
namespace {

std::string read_bytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

void expect_same(const Model& a, const Model& b) {
  EXPECT_EQ(a.mesh.source, b.mesh.source);
  EXPECT_EQ(a.mesh.has_uvs, b.mesh.has_uvs);
  EXPECT_EQ(a.mesh.positions, b.mesh.positions);  // exactly: doubles sent bit for bit
  ASSERT_EQ(a.mesh.triangles.size(), b.mesh.triangles.size());
  for (size_t i = 0; i < a.mesh.triangles.size(); ++i) {
    const MeshTriangle &s = a.mesh.triangles[i], &t = b.mesh.triangles[i];
    for (int k = 0; k < 3; ++k) {
      ASSERT_EQ(s.v[k], t.v[k]) << "triangle " << i;
      ASSERT_EQ(s.uv[k], t.uv[k]) << "triangle " << i;
    }
    ASSERT_EQ(s.line, t.line);
  }
  EXPECT_EQ(a.triangle_material, b.triangle_material);
  ASSERT_EQ(a.materials.size(), b.materials.size());
  for (size_t i = 0; i < a.materials.size(); ++i) {
    EXPECT_EQ(a.materials[i].name, b.materials[i].name);
    EXPECT_EQ(a.materials[i].texture, b.materials[i].texture);
  }
}

TEST(ModelIsolation, AssimpsKnownCrashIsAnErrorNamingTheFile) {
  // The fuzz harness's input: the first byte picks the format (0: OBJ), the rest is the file.
  const std::string input = read_bytes(std::string(TEXSIM_SOURCE_DIR) +
                                       "/testbench/fuzz/known-crashes/assimp-obj-segv-5ed98ee7");
  ASSERT_GT(input.size(), 1u);
  ASSERT_EQ(input[0], '\0');
  try {
    (void)parse_model(input.substr(1), "obj", "crash.obj");
    FAIL() << "no error";
  } catch (const ChildFailure& e) {
    EXPECT_EQ(e.kind, ChildFailure::Kind::Signal);
    EXPECT_EQ(std::string(e.what()),
              "crash.obj: the model importer (Assimp) crashed (SIGSEGV: segmentation fault): "
              "the file is not one it reads safely");
  }
}

TEST(ModelIsolation, ShippedModelsLoadAsInProcess) {
  for (const char* name : {"cat.3ds", "horse.3ds"}) {
    const std::string path = std::string("/usr/share/glmark2/models/") + name;
    const Model child = load_model(path, "");
    const Model here = load_model(path, "", {}, ImportIn::ThisProcess);
    EXPECT_GT(child.mesh.triangles.size(), 7000u) << name;
    expect_same(child, here);
  }
}

TEST(ModelIsolation, AnObjWithItsMaterialsLoadsAsInProcessAndItsFilesAreInputs) {
  TempDir dir("model_isolation");
  std::ofstream(dir.file("m.obj"), std::ios::binary)
      << "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
         "usemtl skin\nf 1/1 2/2 3/3\nusemtl bare\nf 1/1 3/3 4/4\n";
  std::ofstream(dir.file("m.mtl"), std::ios::binary)
      << "newmtl skin\nmap_Kd skin.png\nnewmtl bare\nKd 1 0 0\n";
  const Model child = load_model("m.obj", dir.file(""));
  expect_same(child, load_model("m.obj", dir.file(""), {}, ImportIn::ThisProcess));
  ASSERT_EQ(child.mesh.triangles.size(), 2u);
  // The MTL was opened by the child only: the run must still refuse to overwrite it.
  EXPECT_NE(error_of([&] {
              refuse_overwriting_input(dir.file("m.mtl"));
            }).find("is an input of this run"),
            std::string::npos);
  // An error of the import comes back as it was.
  std::ofstream(dir.file("bare.obj"), std::ios::binary) << "v 0 0 0\n";
  EXPECT_EQ(error_of([&] { (void)load_model(dir.file("bare.obj"), ""); }), error_of([&] {
              (void)load_model(dir.file("bare.obj"), "", {}, ImportIn::ThisProcess);
            }));
}

TEST(ModelIsolation, ModelsLoadFromThreadsAtOnce) {
  std::vector<size_t> got(4);
  std::vector<std::string> errors(4);
  std::vector<std::thread> threads;
  for (size_t i = 0; i < got.size(); ++i) {
    threads.emplace_back([&got, &errors, i] {
      // An error is this test's failure, not std::terminate (which would leave children behind).
      try {
        got[i] = load_model("/usr/share/glmark2/models/horse.3ds", "").mesh.triangles.size();
      } catch (const std::exception& e) {
        errors[i] = e.what();
      }
    });
  }
  for (std::thread& t : threads) t.join();
  for (size_t i = 0; i < got.size(); ++i) EXPECT_EQ(got[i], 7172u) << errors[i];
}

// run_isolated with a child that does `f` and a parent that reads everything.
std::string run(const std::function<void(ByteSink&)>& f, ChildLimits limits = {}) {
  return error_of([&] {
    run_isolated(
        "in.x", "the reader", f,
        [](ByteSource& in) {
          char buf[256];
          while (in.read_some(buf, sizeof buf) != 0) {
          }
        },
        limits);
  });
}

TEST(IsolatedChild, ADeadHangingOrFailingChildIsAnError) {
  EXPECT_EQ(run([](ByteSink&) { ::raise(SIGSEGV); }),
            "in.x: the reader crashed (SIGSEGV: segmentation fault): the file is not one it "
            "reads safely");
  EXPECT_EQ(run([](ByteSink&) { std::abort(); }).find("in.x: the reader crashed (SIGABRT"), 0u);
  EXPECT_EQ(run([](ByteSink&) { ::_exit(7); }), "in.x: the reader exited with status 7");
  EXPECT_EQ(run([](ByteSink&) { throw std::runtime_error("x"); }),
            "in.x: the reader exited with status 3");
  const auto t0 = std::chrono::steady_clock::now();
  ChildLimits quick;
  quick.timeout_ms = 300;
  EXPECT_EQ(run([](ByteSink&) { ::sleep(20); }, quick),
            "in.x: the reader timed out after 300 ms and was killed");
  // Also while it keeps writing (the reader is never starved into waiting forever).
  EXPECT_EQ(run(
                [](ByteSink& out) {
                  for (;;) out.write("x", 1);
                },
                quick),
            "in.x: the reader timed out after 300 ms and was killed");
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(10));
}

TEST(IsolatedChild, AChildEndedBySigtermLeavesTheParentsTemporaryFiles) {
  TempDir dir("isolated_child");
  const std::string tmp = dir.file("out.tmp.1");
  std::ofstream(tmp) << "x";
  install_temp_cleanup();
  track_temp(tmp);
  EXPECT_EQ(run([](ByteSink&) { ::raise(SIGTERM); }).find("in.x: the reader crashed (SIGTERM"), 0u);
  EXPECT_TRUE(std::filesystem::exists(tmp));  // texsim's handler would have removed it
  remove_temp(tmp);
}

TEST(IsolatedChild, TheChildsAddressSpaceIsCapped) {
  ChildLimits small;
  small.extra_address_space = uint64_t{256} << 20;
  std::string got;
  try {
    run_isolated(
        "in.x", "the reader",
        [](ByteSink& out) {
          char refused = 'y';
          try {
            auto p = std::make_unique<char[]>(size_t{2} << 30);
            p[0] = 1;
            refused = p[0] == 1 ? 'n' : '?';
          } catch (const std::bad_alloc&) {
          }
          out.write(&refused, 1);
        },
        [&](ByteSource& in) {
          char c = 0;
          if (in.read_some(&c, 1) == 1) got.assign(1, c);
        },
        small);
  } catch (const ChildFailure& e) {
    // AddressSanitizer (scripts/sanitize.sh) aborts on the refused allocation instead of
    // throwing std::bad_alloc.
    EXPECT_EQ(e.kind, ChildFailure::Kind::Signal) << e.what();
    got = "aborted";
  }
  EXPECT_TRUE(got == "y" || got == "aborted") << got;
}

TEST(IsolatedChild, TheReadersErrorOrTrailingBytesAreErrors) {
  const auto reader_fails = [](ByteSource& in) {
    char c;
    (void)in.read_some(&c, 1);
    throw InputError("in.x", "refused");
  };
  // The child writes more than a pipe holds; the parent stops reading: its error stands.
  EXPECT_EQ(error_of([&] {
              run_isolated(
                  "in.x", "the reader",
                  [](ByteSink& out) {
                    const std::string mb(1 << 20, 'x');
                    for (int i = 0; i < 8; ++i) out.write(mb.data(), mb.size());
                  },
                  reader_fails);
            }),
            "in.x: refused");
  EXPECT_EQ(error_of([&] {
              run_isolated(
                  "in.x", "the reader", [](ByteSink& out) { out.write("ab", 2); },
                  [](ByteSource& in) {
                    char c;
                    ASSERT_EQ(in.read_some(&c, 1), 1u);
                  });
            }),
            "in.x: the reader sent malformed data: bytes after the end of its output");
}

// A valid message of a one-triangle model, then `edit` applied to its bytes.
std::string message_bytes() {
  ModelMessage m;
  m.opened = {"/a/m.obj"};
  m.model.mesh.has_uvs = true;
  m.model.materials = {{"skin", "/a/skin.png"}};
  m.model.mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  MeshTriangle t;
  t.v[0] = 0, t.v[1] = 1, t.v[2] = 2;
  t.uv[1] = {1, 0};
  m.model.mesh.triangles = {t};
  m.model.triangle_material = {0};
  StringSink out;
  write_model_message(out, m);
  return out.bytes;
}

std::string read_error(const std::string& bytes) {
  return error_of([&] {
    StringSource in(bytes);
    (void)read_model_message(in, "m.obj", "the importer", {});
  });
}

TEST(ModelStream, ReadsWhatIsWrittenAndRefusesEveryMalformedPart) {
  const std::string good = message_bytes();
  StringSource in(good);
  const ModelMessage m = read_model_message(in, "m.obj", "the importer", {});
  ASSERT_EQ(m.opened.size(), 1u);
  EXPECT_EQ(m.model.materials[0].texture, "/a/skin.png");
  EXPECT_EQ(m.model.mesh.triangles[0].uv[1], glm::dvec2(1, 0));
  // Offsets: header 8, opened 4 + 4 + 8, status 1, has_uvs 1, materials 4 + 8 + 15,
  // vertices at 53 (count) and 57 (data), triangles' count at 129, data at 133.
  const auto patched = [&](size_t at, const void* v, size_t n) {
    std::string b = good;
    b.replace(at, n, static_cast<const char*>(v), n);
    return b;
  };
  const uint32_t huge = 0xffffffffu;
  const int32_t three = 3;
  const double nan = std::nan("");
  EXPECT_EQ(read_error(good.substr(0, good.size() - 1)),
            "m.obj: the importer sent malformed data: the output ends early, at byte 200");
  EXPECT_EQ(read_error(patched(0, "XXXX", 4)),
            "m.obj: the importer sent malformed data: no TXMI mark, at byte 4");
  EXPECT_EQ(read_error(patched(8, &huge, 4)),
            "m.obj: the importer sent malformed data: opened file count 4294967295 over the "
            "limit, at byte 12");
  EXPECT_EQ(read_error(patched(53, &huge, 4)),
            "m.obj: 4294967295 vertices, over the limit of 4194304");
  EXPECT_EQ(read_error(patched(57, &nan, 8)),
            "m.obj: the importer sent malformed data: vertex coordinate not finite or out of "
            "range, at byte 65");
  EXPECT_EQ(read_error(patched(129, &huge, 4)),
            "m.obj: 4294967295 triangles, over the limit of 4194304 (with the scene's faces "
            "before it)");
  EXPECT_EQ(read_error(patched(133, &three, 4)),
            "m.obj: the importer sent malformed data: vertex index out of range, at byte 137");
  EXPECT_EQ(read_error(good + "x"), "");  // the end mark ends it; run_isolated checks the rest
}

}  // namespace
}  // namespace texsim
