// texsim does not link OpenImageIO (its ~260 libraries cost ~0.2 s at every start): the
// executable's DT_NEEDED entries, read from its ELF dynamic section, name no OpenImageIO library
// while the plugin's do; a run of procedural textures never opens the plugin; a texture file
// does, and without the plugin it is an error naming the library and where it was looked for.
#include <elf.h>
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "blocks/base/input_error.h"
#include "pipeline/image_io/oiio_plugin.h"
#include "pipeline/scene/texture_loader.h"
#include "testbench/lib/cli_harness.h"

namespace {

using namespace cli_harness;  // NOLINT(google-build-using-namespace)

// The DT_NEEDED names of a 64-bit little-endian ELF file (empty if it is not one).
std::vector<std::string> needed_libraries(const std::string& path) {
  const std::string elf = slurp(path);
  std::vector<std::string> names;
  Elf64_Ehdr eh{};
  if (elf.size() < sizeof eh) return names;
  std::memcpy(&eh, elf.data(), sizeof eh);
  if (std::memcmp(eh.e_ident, ELFMAG, SELFMAG) != 0 || eh.e_ident[EI_CLASS] != ELFCLASS64)
    return names;
  std::vector<Elf64_Phdr> ph(eh.e_phnum);
  for (size_t i = 0; i < ph.size(); ++i) {
    const size_t at = eh.e_phoff + i * eh.e_phentsize;
    if (at + sizeof(Elf64_Phdr) > elf.size()) return names;
    std::memcpy(&ph[i], elf.data() + at, sizeof(Elf64_Phdr));
  }
  // Addresses in the dynamic section map to file offsets through the loadable segments.
  const auto offset_of = [&](uint64_t addr) -> uint64_t {
    for (const Elf64_Phdr& p : ph) {
      if (p.p_type == PT_LOAD && addr >= p.p_vaddr && addr < p.p_vaddr + p.p_filesz)
        return addr - p.p_vaddr + p.p_offset;
    }
    return elf.size();
  };
  for (const Elf64_Phdr& p : ph) {
    if (p.p_type != PT_DYNAMIC) continue;
    std::vector<Elf64_Dyn> dyn(p.p_filesz / sizeof(Elf64_Dyn));
    if (p.p_offset + dyn.size() * sizeof(Elf64_Dyn) > elf.size()) return names;
    std::memcpy(dyn.data(), elf.data() + p.p_offset, dyn.size() * sizeof(Elf64_Dyn));
    uint64_t strtab = elf.size();
    for (const Elf64_Dyn& d : dyn) {
      if (d.d_tag == DT_STRTAB) strtab = offset_of(d.d_un.d_ptr);
    }
    for (const Elf64_Dyn& d : dyn) {
      if (d.d_tag == DT_NEEDED && strtab + d.d_un.d_val < elf.size())
        names.emplace_back(elf.c_str() + strtab + d.d_un.d_val);
    }
  }
  return names;
}

std::string plugin_path() {
  return (fs::path(TEXSIM_BINARY).parent_path() / texsim::oiio::kLibraryName).string();
}

TEST(OiioPlugin, TexsimDoesNotLinkOpenImageIO) {
  const std::vector<std::string> needed = needed_libraries(TEXSIM_BINARY);
  std::string all;
  for (const std::string& n : needed) all += n + " ";
  // The reader works: the C library and libpng are there.
  EXPECT_NE(all.find("libc.so"), std::string::npos) << all;
  EXPECT_NE(all.find("libpng"), std::string::npos) << all;
  for (const std::string& n : needed) EXPECT_EQ(n.find("OpenImageIO"), std::string::npos) << n;
}

TEST(OiioPlugin, ThePluginLinksOpenImageIO) {
  std::string all;
  for (const std::string& n : needed_libraries(plugin_path())) all += n + " ";
  EXPECT_NE(all.find("libOpenImageIO"), std::string::npos) << plugin_path() << ": " << all;
}

class PluginCli : public Cli {};

TEST_F(PluginCli, ProceduralRunNeverOpensThePlugin) {
  // A plugin path that cannot load: the run only succeeds if nothing asks for OpenImageIO.
  const Result r = sh("run " + std::string(TEXSIM_SOURCE_DIR) +
                      "/scenes/coords.toml --reference none --no-progress --set "
                      "output.width=32 --set output.height=16 --out " +
                      path("out"));
  ASSERT_EQ(r.code, 0) << r.out;
  const Result bad = shell("TEXSIM_OIIO_PLUGIN=" + path("none.so") + " " + TEXSIM_BINARY + " run " +
                           TEXSIM_SOURCE_DIR +
                           "/scenes/coords.toml --reference none --no-progress --set "
                           "output.width=32 --set output.height=16 --out " +
                           path("out2"));
  ASSERT_EQ(bad.code, 0) << bad.out;
  EXPECT_EQ(slurp(path("out/image.png")), slurp(path("out2/image.png")));
}

TEST_F(PluginCli, TextureFileWithoutThePluginNamesTheLibrary) {
  const std::string scene = std::string(TEXSIM_SOURCE_DIR) + "/scenes/cube.toml";
  const Result r =
      shell("TEXSIM_OIIO_PLUGIN=" + path("missing/libtexsim_oiio.so") + " " + TEXSIM_BINARY +
            " run " + scene + " --reference none --no-progress --out " + path("out"));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("crate-base.png"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(path("missing/libtexsim_oiio.so")), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("TEXSIM_OIIO_PLUGIN"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("internal error"), std::string::npos) << r.out;
  expect_no_outputs(path("out"));
  // A copy of texsim alone in a directory: nothing beside it, so the error lists the places.
  if (fs::exists(texsim::oiio_plugin_candidates().back())) GTEST_SKIP() << "plugin installed";
  fs::copy_file(TEXSIM_BINARY, path("texsim"));
  const Result alone = shell(path("texsim") + " run " + scene +
                             " --reference none --no-progress --out " + path("out3"));
  EXPECT_EQ(alone.code, 2) << alone.out;
  EXPECT_NE(alone.out.find(path("libtexsim_oiio.so") + " (no such file)"), std::string::npos)
      << alone.out;
}

TEST(OiioPlugin, MissingPluginIsAnInputErrorInProcess) {
  ::setenv("TEXSIM_OIIO_PLUGIN", "/nonexistent/libtexsim_oiio.so", 1);
  ASSERT_FALSE(texsim::oiio_plugin_loaded()) << "run this test in its own process (ctest does)";
  try {
    texsim::load_texture("/usr/share/glmark2/textures/crate-base.png", "");
    ADD_FAILURE() << "loaded a texture file without the plugin";
  } catch (const texsim::InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("crate-base.png"), std::string::npos) << what;
    EXPECT_NE(what.find("/nonexistent/libtexsim_oiio.so (no such file)"), std::string::npos)
        << what;
  }
  ::unsetenv("TEXSIM_OIIO_PLUGIN");
}

TEST(OiioPlugin, LoadsOnFirstTextureFile) {
  ::setenv("TEXSIM_OIIO_PLUGIN", plugin_path().c_str(), 1);
  const texsim::Texture t = texsim::load_texture("/usr/share/glmark2/textures/crate-base.png", "");
  EXPECT_TRUE(texsim::oiio_plugin_loaded());
  EXPECT_GT(t.width(0), 0);
  EXPECT_FALSE(texsim::oiio_plugin("test").version().empty());
  ::unsetenv("TEXSIM_OIIO_PLUGIN");
}

}  // namespace
