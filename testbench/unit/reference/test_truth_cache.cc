// The truth cache (pipeline/reference/truth_cache.h): SHA-256 and CRC-64 against their
// standards' vectors; a key that changes with every input class of the truth and with nothing
// else; entries that fail their checks when a byte is flipped, the file is cut or the header
// names another key; eviction to the limit; concurrent writers; and runs whose outputs are
// byte-identical with and without the cache, whose second run hits, and whose damaged entry
// is recomputed.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "blocks/base/input_error.h"
#include "blocks/base/sha256.h"
#include "pipeline/app/run.h"
#include "pipeline/reference/truth_cache.h"
#include "pipeline/reference/truth_key.h"
#include "testbench/lib/temp_dir.h"

namespace texsim {
namespace {

namespace fs = std::filesystem;

std::string sha(const std::string& s) {
  Sha256 h;
  h.update(s.data(), s.size());
  return Sha256::hex(h.finish());
}

TEST(Sha256, Fips180Vectors) {
  EXPECT_EQ(sha(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(sha("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(sha("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  EXPECT_EQ(
      sha("abcdefghbcdefghicdefghijdefghijkefghijklfghijklmghijklmnhijklmnoijklmnopjklmnopqklm"
          "nopqrlmnopqrsmnopqrstnopqrstu"),
      "cf5b16a778af8380036ce59e7b0492370b249b11e8f07a51afac45037afee9d1");
  EXPECT_EQ(sha(std::string(1000000, 'a')),
            "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(Sha256, PiecesGiveTheWholesDigest) {
  const std::string s(1000, 'x');
  for (size_t cut : {0, 1, 55, 56, 63, 64, 65, 999}) {
    Sha256 h;
    h.update(s.data(), cut);
    h.update(s.data() + cut, s.size() - cut);
    EXPECT_EQ(Sha256::hex(h.finish()), sha(s)) << cut;
  }
}

TEST(TruthCache, PayloadChecksumIsCrc64Xz) {
  EXPECT_EQ(truth_payload_crc("123456789", 9), 0x995dc9bbdf1939faULL);
}

constexpr size_t kTexels8 = 256, kTexels4 = 64;  // floats of an 8×8 and a 4×4 RGBA level

// A small set of inputs of every class the key covers.
struct KeyFixture {
  TextureSet set;
  std::vector<ScenePrimitive> prims{ScenePrimitive{}, ScenePrimitive{}};
  TruthKeyInputs in;
  KeyFixture() {
    std::vector<float> px(kTexels8, 0.25f);
    set.add(Texture::from_rgba("a", 8, 8, px, TexelFormat::Rgba8, true));
    set.add(Texture::from_rgba("b", 8, 8, px, TexelFormat::Rgba32f, true));
    prims[1].origin = {1, 0, -2};
    in.width = 64;
    in.height = 48;
    in.cameras = {Camera{}};
    in.primitives = &prims;
    in.textures = &set;
    in.materials = {{0, AddressMode::Wrap, AddressMode::Wrap, false},
                    {1, AddressMode::Clamp, AddressMode::Wrap, false}};
  }
  TruthKey key() const { return truth_key(in); }
};

TEST(TruthKey, SameInputsSameKey) {
  KeyFixture a, b;
  EXPECT_EQ(a.key(), b.key());
  // Names are not content: a texture of the same texels under another name keeps the key.
  TextureSet renamed;
  std::vector<float> px(kTexels8, 0.25f);
  renamed.add(Texture::from_rgba("other", 8, 8, px, TexelFormat::Rgba8, true));
  renamed.add(Texture::from_rgba("names", 8, 8, px, TexelFormat::Rgba32f, true));
  b.in.textures = &renamed;
  EXPECT_EQ(a.key(), b.key());
}

// Every input class of the truth, changed alone, changes the key.
TEST(TruthKey, EveryInputClassChangesTheKey) {
  const TruthKey base = KeyFixture().key();
  auto changed = [&](auto&& edit) {
    KeyFixture f;
    edit(f);
    return f.key() != base;
  };
  EXPECT_TRUE(changed([](KeyFixture& f) { f.in.width = 65; }));
  EXPECT_TRUE(changed([](KeyFixture& f) { f.in.height = 47; }));
  EXPECT_TRUE(changed([](KeyFixture& f) { f.in.cameras[0].position.x += 1e-12; }));
  EXPECT_TRUE(changed([](KeyFixture& f) { f.in.cameras[0].tan_half_fov_y *= 1.0L + 1e-18L; }));
  EXPECT_TRUE(changed([](KeyFixture& f) { f.in.cameras[0].orthographic = true; }));
  EXPECT_TRUE(changed([](KeyFixture& f) { f.in.cameras[0].width = 65; }));
  // The frames of a camera path: one more frame, or one frame's camera moved.
  EXPECT_TRUE(changed([](KeyFixture& f) { f.in.cameras.push_back(Camera{}); }));
  EXPECT_TRUE(changed([](KeyFixture& f) {
    f.in.cameras.push_back(Camera{});
    f.in.cameras.back().look_at.z = -11;
  }));
  EXPECT_TRUE(changed([](KeyFixture& f) { f.prims[0].edge_u.y = 0.5; }));
  EXPECT_TRUE(changed([](KeyFixture& f) { f.prims[1].uv_origin.x = 0.5; }));
  EXPECT_TRUE(changed([](KeyFixture& f) { f.prims[1].shape = ScenePrimitive::Shape::Triangle; }));
  EXPECT_TRUE(changed([](KeyFixture& f) { f.prims[0].cull_back = true; }));
  EXPECT_TRUE(changed([](KeyFixture& f) { f.prims[0].material = 1; }));
  EXPECT_TRUE(changed([](KeyFixture& f) { f.prims.pop_back(); }));
  // Texture content: one texel of level 0, one of a smaller level, the format.
  EXPECT_TRUE(changed([](KeyFixture& f) {
    std::vector<float> px(kTexels8, 0.25f);
    px[4 * 9 + 1] = 0.5f;
    f.set[0] = Texture::from_rgba("a", 8, 8, px, TexelFormat::Rgba8, true);
  }));
  EXPECT_TRUE(changed([](KeyFixture& f) {
    std::vector<std::vector<float>> lv = {std::vector<float>(kTexels8, 0.25f),
                                          std::vector<float>(kTexels4, 0.3f)};
    f.set[1] = Texture::from_levels("b", {8, 4}, {8, 4}, lv, TexelFormat::Rgba32f);
  }));
  EXPECT_TRUE(changed([](KeyFixture& f) {
    std::vector<float> px(kTexels8, 0.25f);
    f.set[1] = Texture::from_rgba("b", 8, 8, px, TexelFormat::Rgba8, true);
  }));
  // Materials: texture, address modes, relief or lighting.
  EXPECT_TRUE(changed([](KeyFixture& f) { f.in.materials[0].texture = 1; }));
  EXPECT_TRUE(changed([](KeyFixture& f) { f.in.materials[0].address_u = AddressMode::Mirror; }));
  EXPECT_TRUE(changed([](KeyFixture& f) { f.in.materials[1].address_v = AddressMode::Clamp; }));
  EXPECT_TRUE(changed([](KeyFixture& f) { f.in.materials[1].surface = true; }));
  // [reference].
  EXPECT_TRUE(changed([](KeyFixture& f) { f.in.pixel = TruthPixel::Gaussian; }));
  EXPECT_TRUE(changed([](KeyFixture& f) { f.in.samples = 8; }));
}

std::vector<TruthRecord> some_records(int n, double salt = 0) {
  std::vector<TruthRecord> r;
  for (int i = 0; i < n; ++i) {
    TruthRecord t;
    t.id = {0, static_cast<uint32_t>(i % 3), static_cast<uint32_t>(i), 7, 1, 0};
    t.rgba[0] = 0.1 * i + salt;
    t.rgba[3] = 1;
    t.samples = i + 9;
    r.push_back(t);
  }
  return r;
}

TruthKey key_of(uint8_t b) {
  TruthKey k{};
  k.fill(b);
  return k;
}

TEST(TruthEntry, RoundTripAndEveryDamageIsFound) {
  const TruthKey key = key_of(7);
  const std::vector<TruthRecord> recs = some_records(50);
  const std::string e = encode_truth_entry(key, recs);
  ASSERT_EQ(e.size(), kTruthHeaderBytes + 50 * sizeof(TruthRecord));
  const std::vector<TruthRecord> back = decode_truth_entry(e, "x.truth", &key);
  ASSERT_EQ(back.size(), recs.size());
  EXPECT_EQ(std::memcmp(back.data(), recs.data(), e.size() - kTruthHeaderBytes), 0);
  auto error = [&](const std::string& bytes, const TruthKey& k) {
    try {
      decode_truth_entry(bytes, "x.truth", &k);
    } catch (const InputError& err) {
      return std::string(err.what());
    }
    return std::string("(accepted)");
  };
  std::string flipped = e;
  flipped[kTruthHeaderBytes + 100] ^= 1;  // a payload byte
  EXPECT_NE(error(flipped, key).find("checksum"), std::string::npos) << error(flipped, key);
  EXPECT_NE(error(e.substr(0, e.size() - 1), key).find("truncated"), std::string::npos);
  EXPECT_NE(error(e.substr(0, 10), key).find("truncated"), std::string::npos);
  EXPECT_NE(error(e, key_of(8)).find("not the file's key"), std::string::npos);
  std::string magic = e;
  magic[0] = 'X';
  EXPECT_NE(error(magic, key).find("magic"), std::string::npos);
  std::string version = e;
  version[8] = 9;
  EXPECT_NE(error(version, key).find("version"), std::string::npos);
  EXPECT_NE(error(e, key).find("(accepted)"), std::string::npos);
  EXPECT_NE(error(e, key_of(8)).find("x.truth"), std::string::npos);  // names the file
}

TEST(TruthTable, FindsEveryRecordAndNothingElse) {
  const TruthTable t(some_records(1000));
  for (const TruthRecord& r : t.records()) {
    const TruthRecord* f = t.find(r.id);
    ASSERT_NE(f, nullptr);
    EXPECT_EQ(f->samples, r.samples);
  }
  EXPECT_EQ(t.find({0, 0, 1, 7, 1, 0}), nullptr);  // prim 0 never has x = 1
  EXPECT_EQ(t.find({1, 0, 0, 7, 1, 0}), nullptr);  // another frame
  // By position, and with a wrong hint through the index.
  EXPECT_EQ(t.find(t.records()[5].id, 5), &t.records()[5]);
  EXPECT_EQ(t.find(t.records()[5].id, 6), &t.records()[5]);
  EXPECT_EQ(t.find(t.records()[5].id, 1u << 30), &t.records()[5]);
  // A repeated id: the index gives the first record.
  std::vector<TruthRecord> twice = some_records(10);
  twice.push_back(twice[3]);
  twice.back().samples = -1;
  EXPECT_EQ(TruthTable(twice).find(twice[3].id)->samples, twice[3].samples);
  const auto m = t.merged(some_records(1001));
  EXPECT_EQ(m->records().size(), 2001u);
  EXPECT_EQ(m->find(some_records(1001).back().id)->samples, 1009);
}

TruthCacheConfig config_in(const TempDir& d, uint64_t max_bytes = uint64_t{1} << 30) {
  TruthCacheConfig c;
  c.dir = d.file("truth");
  c.max_bytes = max_bytes;
  return c;
}

TEST(TruthCache, HitAfterMissFromMemoryThenFromDisk) {
  TempDir d("truth_hit");
  TruthCache::forget_memory();
  TruthCache c(config_in(d));
  const TruthKey key = key_of(1);
  EXPECT_EQ(c.find(key), nullptr);
  c.store(key, std::make_shared<const TruthTable>(some_records(20)));
  ASSERT_NE(c.find(key), nullptr);
  EXPECT_STREQ(c.found_in(), "memory");
  TruthCache::forget_memory();
  const auto t = c.find(key);
  ASSERT_NE(t, nullptr);
  EXPECT_STREQ(c.found_in(), "disk");
  EXPECT_EQ(t->records().size(), 20u);
  TruthCacheConfig off = config_in(d);
  off.enabled = false;
  EXPECT_EQ(TruthCache(off).find(key), nullptr);  // --no-truth-cache reads nothing
}

TEST(TruthCache, DamagedEntriesAreReportedRemovedAndNeverUsed) {
  TempDir d("truth_damage");
  TruthCache c(config_in(d));
  const TruthKey key = key_of(2);
  const std::string path = c.entry_path(key);
  auto damage = [&](auto&& edit) {
    TruthCache::forget_memory();
    c.store(key, std::make_shared<const TruthTable>(some_records(30)));
    TruthCache::forget_memory();
    std::string bytes;
    {
      std::ifstream in(path, std::ios::binary);
      bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    edit(bytes);
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
    testing::internal::CaptureStderr();
    const auto t = c.find(key);
    const std::string err = testing::internal::GetCapturedStderr();
    EXPECT_EQ(t, nullptr);
    EXPECT_NE(err.find("warning: truth cache: " + path), std::string::npos) << err;
    EXPECT_FALSE(fs::exists(path));
  };
  damage([](std::string& b) { b[kTruthHeaderBytes + 350] ^= 0x10; });
  damage([](std::string& b) { b.resize(b.size() - 64); });
  damage([](std::string& b) { b.resize(40); });
  damage([](std::string& b) { b[16] ^= 1; });  // the header's key
}

TEST(TruthCache, EvictsLeastRecentlyUsedToTheLimit) {
  TempDir d("truth_evict");
  TruthCache::forget_memory();
  const uint64_t entry = kTruthHeaderBytes + 100 * sizeof(TruthRecord);
  TruthCache c(config_in(d, 2 * entry + 10));  // room for two entries
  const auto t = std::make_shared<const TruthTable>(some_records(100));
  const auto now = fs::file_time_type::clock::now();
  c.store(key_of(1), t);
  fs::last_write_time(c.entry_path(key_of(1)), now - std::chrono::hours(3));
  c.store(key_of(2), t);
  fs::last_write_time(c.entry_path(key_of(2)), now - std::chrono::hours(2));
  TruthCache::forget_memory();
  ASSERT_NE(c.find(key_of(1)), nullptr);  // a hit: key 1 is now the most recent
  c.store(key_of(3), t);
  EXPECT_TRUE(fs::exists(c.entry_path(key_of(1))));
  EXPECT_FALSE(fs::exists(c.entry_path(key_of(2))));
  EXPECT_TRUE(fs::exists(c.entry_path(key_of(3))));
  // An entry larger than the whole limit is never written.
  TruthCache tiny(config_in(d, entry - 1));
  tiny.store(key_of(4), t);
  EXPECT_FALSE(fs::exists(tiny.entry_path(key_of(4))));
  evict_truth_entries(d.file("no-such-dir"), 0);  // a directory that vanished: nothing to do
}

TEST(TruthCache, ConcurrentWritersOfOneKeyLeaveOneWholeEntry) {
  TempDir d("truth_concurrent");
  const TruthKey key = key_of(5);
  const auto t = std::make_shared<const TruthTable>(some_records(2000));
  // Two processes, each with two threads, write the same key over and over.
  std::vector<pid_t> kids;
  for (int p = 0; p < 2; ++p) {
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      std::vector<std::thread> th;
      th.reserve(2);
      for (int i = 0; i < 2; ++i) {
        th.emplace_back([&] {
          TruthCache c(config_in(d));
          for (int k = 0; k < 20; ++k) c.store(key, t);
        });
      }
      for (auto& x : th) x.join();
      ::_exit(0);
    }
    kids.push_back(pid);
  }
  for (pid_t pid : kids) {
    int status = 0;
    ::waitpid(pid, &status, 0);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  }
  TruthCache::forget_memory();
  TruthCache c(config_in(d));
  const auto back = c.find(key);
  ASSERT_NE(back, nullptr);
  EXPECT_EQ(back->records().size(), 2000u);
  size_t files = 0;
  for (const auto& e : fs::directory_iterator(d.file("truth"))) files += e.is_regular_file();
  EXPECT_EQ(files, 1u);  // no temporary file left behind
}

TEST(TruthCache, UnwritableDirectoryWarnsAndGoesOn) {
  TempDir d("truth_unwritable");
  std::ofstream(d.file("file")) << "x";
  TruthCacheConfig cfg;
  cfg.dir = d.file("file") + "/truth";  // below a regular file: never a directory
  TruthCache c(cfg);
  testing::internal::CaptureStderr();
  EXPECT_NO_THROW(c.store(key_of(6), std::make_shared<const TruthTable>(some_records(3))));
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("cannot write entries in " + cfg.dir), std::string::npos) << err;
}

// Sets an environment variable for one scope.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) {
    if (const char* v = std::getenv(name)) old_ = v, had_ = true;
    if (value) {
      ::setenv(name, value, 1);
    } else {
      ::unsetenv(name);
    }
  }
  ~ScopedEnv() {
    if (had_) {
      ::setenv(name_, old_.c_str(), 1);
    } else {
      ::unsetenv(name_);
    }
  }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  const char* name_;
  std::string old_;
  bool had_ = false;
};

TEST(TruthCacheConfig, DirectoryAndLimitFromTheEnvironment) {
  {
    ScopedEnv a("TEXSIM_CACHE_DIR", "/tmp/tc"), b("TEXSIM_TRUTH_CACHE_MAX", "512M");
    const TruthCacheConfig c = TruthCacheConfig::from_env(true);
    EXPECT_EQ(c.dir, "/tmp/tc/truth");
    EXPECT_EQ(c.max_bytes, uint64_t{512} << 20);
  }
  {
    ScopedEnv a("TEXSIM_CACHE_DIR", nullptr), b("XDG_CACHE_HOME", "/x"),
        m("TEXSIM_TRUTH_CACHE_MAX", nullptr);
    EXPECT_EQ(TruthCacheConfig::from_env(true).dir, "/x/texsim/truth");
    EXPECT_EQ(TruthCacheConfig::from_env(true).max_bytes, uint64_t{2} << 30);
  }
  {
    ScopedEnv a("TEXSIM_CACHE_DIR", nullptr), b("XDG_CACHE_HOME", nullptr), h("HOME", "/h");
    EXPECT_EQ(TruthCacheConfig::from_env(true).dir, "/h/.cache/texsim/truth");
  }
  for (const char* bad : {"lots", "-1", "2T", "1.5G", "99999999999999999999"}) {
    ScopedEnv m("TEXSIM_TRUTH_CACHE_MAX", bad);
    EXPECT_THROW(TruthCacheConfig::from_env(true), InputError) << bad;
  }
  EXPECT_FALSE(TruthCacheConfig::from_env(false).enabled);
}

// Runs of a small scene (two materials, wrap and clamp) in-process, cache in a temporary
// directory.
const char* kScene = R"([output]
width = 48
height = 32
[camera]
position = [0.0, 1.0, 0.0]
look_at = [0.0, 0.3, -10.0]
[textures.checker]
source = "procedural:checker?size=64&cells=8"
[materials.floor]
texture = "checker"
filter = { mode = "trilinear", address = "wrap" }
[materials.wall]
texture = "checker"
filter = { mode = "bilinear", address = "clamp" }
[[planes]]
material = "floor"
origin = [-10.0, 0.0, -0.5]
edge_u = [20.0, 0.0, 0.0]
edge_v = [0.0, 0.0, -20.0]
uv_scale = [6.0, 6.0]
[[planes]]
material = "wall"
origin = [-2.0, 0.0, -8.0]
edge_u = [3.0, 0.0, -1.0]
edge_v = [0.0, 2.0, 0.0]
)";

struct RunFixture {
  TempDir dir{"truth_run"};
  ScopedEnv env{"TEXSIM_CACHE_DIR", dir.file("cache").c_str()};
  std::string scene = dir.file("s.toml");
  RunFixture() { std::ofstream(scene) << kScene; }
  // The run's log; its outputs in dir/<out>.
  std::string run(const std::string& out, bool cache, std::vector<std::string> sets = {}) {
    RunOptions o;
    o.scene = scene;
    o.out = dir.file(out);
    o.threads = 2;
    o.command = "texsim run s.toml";
    o.truth_cache = cache;
    o.overrides = std::move(sets);
    std::ostringstream log;
    run_simulation(o, log);
    return log.str();
  }
  std::string bytes(const std::string& f) const {
    std::ifstream in(dir.file(f), std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
  void expect_same_outputs(const std::string& a, const std::string& b) const {
    for (const char* f : {"report.json", "report.md", "image.png", "reference.png", "error.png"})
      EXPECT_EQ(bytes(a + "/" + f), bytes(b + "/" + f)) << f;
  }
};

TEST(TruthCacheRun, ByteIdenticalWithAndWithoutTheCacheAndHitsAfterAMiss) {
  RunFixture f;
  TruthCache::forget_memory();
  const std::string off = f.run("off", false);
  EXPECT_EQ(off.find("truth cache"), std::string::npos);
  EXPECT_NE(f.run("miss", true).find("from nowhere (a miss)"), std::string::npos);
  EXPECT_NE(f.run("memory", true).find("from memory"), std::string::npos);
  TruthCache::forget_memory();
  const std::string disk = f.run("disk", true);
  EXPECT_NE(disk.find("from disk"), std::string::npos) << disk;
  EXPECT_EQ(disk.find(" 0 of"), std::string::npos) << disk;
  for (const char* o : {"miss", "memory", "disk"}) f.expect_same_outputs("off", o);
  // The unit's configuration is not the truth's: another filter shares the entry.
  EXPECT_NE(f.run("filter", true, {"materials.floor.filter.mode=bilinear"}).find("from memory"),
            std::string::npos);
  // An address mode is the truth's: a new key.
  EXPECT_NE(f.run("clamp", true, {"materials.floor.filter.address=clamp"}).find("a miss"),
            std::string::npos);
}

TEST(TruthCacheRun, ADamagedEntryIsRecomputedWithTheSameResult) {
  RunFixture f;
  TruthCache::forget_memory();
  f.run("first", true);
  TruthCache::forget_memory();
  const fs::path dir = f.dir.file("cache/truth");
  std::vector<fs::path> entries;
  // The truth's entry and those of its finer tiers (the pixels the run refined): each damaged.
  for (const auto& e : fs::directory_iterator(dir)) entries.push_back(e.path());
  ASSERT_GE(entries.size(), 2u);
  for (const fs::path& e : entries) {
    std::fstream io(e, std::ios::in | std::ios::out | std::ios::binary);
    io.seekp(static_cast<std::streamoff>(kTruthHeaderBytes + 20));
    io.put('\x5a');
  }
  testing::internal::CaptureStderr();
  const std::string log = f.run("again", true);
  const std::string err = testing::internal::GetCapturedStderr();
  for (const fs::path& e : entries) EXPECT_NE(err.find(e.string()), std::string::npos) << err;
  EXPECT_NE(log.find("a miss"), std::string::npos) << log;
  f.expect_same_outputs("first", "again");
  TruthCache::forget_memory();
  EXPECT_NE(f.run("third", true).find("from disk"), std::string::npos);  // rewritten whole
}

}  // namespace
}  // namespace texsim
