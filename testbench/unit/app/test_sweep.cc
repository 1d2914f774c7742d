// Sweeps: the grid expands into numbered jobs in a fixed order, shards partition them, each
// job writes its own report, and merge combines them into one table; GNU parallel over shards
// gives the same table as one local run.
#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <sstream>

#include "blocks/base/input_error.h"
#include "pipeline/app/sweep.h"
#include "testbench/lib/cli_harness.h"
#include "testbench/lib/temp_dir.h"

namespace texsim {
namespace {

using cli_harness::Result;
using cli_harness::shell;
using cli_harness::slurp;

const char* kSweep = R"([sweep]
scenes = ["default"]
out = "res"
[grid]
"output.width" = [40, 48]
"pipeline.fifo_depth" = [2, 4, 8]
"output.height" = [30]
)";

TEST(Sweep, GridExpandsInFileOrderLastKeyFastest) {
  TempDir d("sweep");
  std::ofstream(d.file("s.toml")) << kSweep;
  const Sweep s = load_sweep(d.file("s.toml"));
  ASSERT_EQ(s.jobs.size(), 6u);
  EXPECT_EQ(s.out, d.file("res"));
  // toml++ keeps a table's keys sorted: output.height, output.width, pipeline.fifo_depth.
  EXPECT_EQ(s.jobs[0].overrides, (std::vector<std::string>{"output.height=30", "output.width=40",
                                                           "pipeline.fifo_depth=2"}));
  EXPECT_EQ(s.jobs[1].overrides[2], "pipeline.fifo_depth=4");
  EXPECT_EQ(s.jobs[3].overrides[1], "output.width=48");
  for (int i = 0; i < 6; ++i) EXPECT_EQ(s.jobs[static_cast<size_t>(i)].id, i);
}

TEST(Sweep, ShippedExampleExpands) {
  const Sweep s = load_sweep(std::string(TEXSIM_SOURCE_DIR) + "/scenes/sweeps/cache_fifo.toml");
  ASSERT_EQ(s.jobs.size(), 12u);
  EXPECT_EQ(s.jobs[0].scene, "default");
  EXPECT_EQ(s.jobs[6].scene, std::string(TEXSIM_SOURCE_DIR) + "/scenes/sweeps/../coords.toml");
  EXPECT_EQ(s.jobs[11].overrides,
            (std::vector<std::string>{"pipeline.cache.size_bytes=65536", "pipeline.fifo_depth=8"}));
}

TEST(Sweep, BadSweepFilesNameLineAndColumn) {
  TempDir d("sweep");
  const auto error = [&](const std::string& text) {
    std::ofstream(d.file("s.toml")) << text;
    try {
      load_sweep(d.file("s.toml"));
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string f = d.file("s.toml");
  EXPECT_EQ(error("[grid]\nx = [1]\n"),
            f + ": needs a [sweep] table with scenes = [...] or traces = [...]");
  EXPECT_EQ(error("[sweep]\nscenes = []\n"), f + ": sweep: scenes and traces are both empty");
  EXPECT_EQ(error("[sweep]\nscenes = [\"default\"]\n[grid]\n\"a.b\" = []\n"),
            f + ":4:9: grid.a.b: expected a non-empty array of values");
  EXPECT_EQ(error("[sweep]\nscenes = [1]\n"), f + ":2:11: sweep.scenes: expected a string");
  EXPECT_EQ(error("[sweep]\nscene = [\"default\"]\n"),
            f + ":2:9: sweep: unknown key 'scene' (known: scenes, traces, out)");
}

TEST(Sweep, ShardsRunEveryJobOnceAndMergeMatchesOneRun) {
  TempDir d("sweep");
  std::ofstream(d.file("s.toml")) << kSweep;
  const std::string bin = TEXSIM_BINARY, s = d.file("s.toml");
  Result r = shell(bin + " sweep " + s + " --jobs 2 --out " + d.file("all") + " && " + bin +
                   " merge " + d.file("all") + " --out " + d.file("all"));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("texsim sweep: 6 of 6 jobs done"), std::string::npos) << r.out;
  for (int k = 1; k <= 3; ++k) {
    std::string cmd = bin;
    cmd.append(" sweep ").append(s).append(" --shard ").append(std::to_string(k));
    cmd.append("/3 --out ").append(d.file("sh"));
    r = shell(cmd);
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("2 of 2 jobs done"), std::string::npos) << r.out;
  }
  ASSERT_EQ(shell(bin + " merge " + d.file("sh") + " --out " + d.file("sh")).code, 0);
  const std::string all = slurp(d.file("all/merged.csv"));
  EXPECT_EQ(all, slurp(d.file("sh/merged.csv")));
  // The plot of error against cost: a PNG.
  EXPECT_EQ(slurp(d.file("sh/merged.png")).substr(1, 3), "PNG");
  std::istringstream rows(all);
  std::string line;
  std::set<std::string> cycles;
  int n = 0;
  while (std::getline(rows, line)) {
    if (n++ == 0) {
      EXPECT_EQ(line.rfind("job,scene,trace,overrides,fragments,cycles,", 0), 0u) << line;
      continue;
    }
    cycles.insert(line);
  }
  EXPECT_EQ(n, 7);  // header and six jobs, each its own row
  EXPECT_EQ(cycles.size(), 6u);
  EXPECT_NE(all.find("output.height=30; output.width=48; pipeline.fifo_depth=8"),
            std::string::npos);
}

TEST(Sweep, GnuParallelOverShardsGivesTheSameTable) {
  if (shell("command -v parallel").code != 0) GTEST_SKIP() << "GNU parallel is not installed";
  TempDir d("sweep");
  std::ofstream(d.file("s.toml")) << kSweep;
  const std::string bin = TEXSIM_BINARY, s = d.file("s.toml");
  ASSERT_EQ(shell(bin + " sweep " + s + " --out " + d.file("one") + " && " + bin + " merge " +
                  d.file("one") + " --out " + d.file("one"))
                .code,
            0);
  const Result r = shell("parallel --will-cite -j 2 " + bin + " sweep " + s +
                         " --shard {}/3 --out " + d.file("par") + " ::: 1 2 3 && " + bin +
                         " merge " + d.file("par") + " --out " + d.file("par"));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_EQ(slurp(d.file("one/merged.csv")), slurp(d.file("par/merged.csv")));
}

TEST(Sweep, SlurmScriptIsAJobArrayOverTheJobs) {
  TempDir d("sweep");
  std::ofstream(d.file("s.toml")) << kSweep;
  const std::string bin = TEXSIM_BINARY;
  const Result r = shell(bin + " sweep " + d.file("s.toml") + " --slurm --out " + d.file("o"));
  ASSERT_EQ(r.code, 0) << r.out;
  const std::string script = slurp(d.file("o/sweep.sbatch"));
  EXPECT_NE(script.find("#SBATCH --array=0-5\n"), std::string::npos) << script;
  EXPECT_NE(script.find("--job \"$SLURM_ARRAY_TASK_ID\""), std::string::npos) << script;
  // What one array task runs: job 4 alone.
  const Result one =
      shell(bin + " sweep " + d.file("s.toml") + " --out " + d.file("o") + " --job 4");
  ASSERT_EQ(one.code, 0) << one.out;
  EXPECT_TRUE(std::filesystem::exists(d.file("o/job-00004/report.json")));
  EXPECT_FALSE(std::filesystem::exists(d.file("o/job-00003")));
  EXPECT_EQ(shell(bin + " sweep " + d.file("s.toml") + " --job 6").code, 2);
}

// A real single-node Slurm started for the test (scripts/slurm-local.sh: munged, slurmctld and
// slurmd with everything in a temporary directory): the job array of `sweep --slurm` runs every
// job and the merged table equals the local run's. Skipped, with the reason, where Slurm cannot
// start (not installed, not root, a daemon that does not come up).
TEST(Sweep, SlurmJobArrayOnALocalClusterGivesTheSameTable) {
  TempDir d("slurm");
  const std::string slurm = "bash " + std::string(TEXSIM_SOURCE_DIR) + "/scripts/slurm-local.sh ";
  const std::string cluster = d.file("cluster");
  const Result up = shell(slurm + "start " + cluster);
  if (up.code == 77) GTEST_SKIP() << "Slurm cannot run here: " << up.out;
  ASSERT_EQ(up.code, 0) << up.out;
  struct Stop {
    std::string command;
    ~Stop() { (void)shell(command); }
  } stop{slurm + "stop " + cluster};
  std::ofstream(d.file("s.toml")) << kSweep;
  const std::string bin = TEXSIM_BINARY, s = d.file("s.toml");
  ASSERT_EQ(shell(bin + " sweep " + s + " --out " + d.file("one") + " && " + bin + " merge " +
                  d.file("one") + " --out " + d.file("one"))
                .code,
            0);
  const std::string env = "SLURM_CONF=" + cluster + "/slurm.conf ";
  ASSERT_EQ(shell(bin + " sweep " + s + " --slurm --out " + d.file("sl")).code, 0);
  const Result run = shell(env + "timeout 300 sbatch --wait " + d.file("sl/sweep.sbatch") + " && " +
                           bin + " merge " + d.file("sl") + " --out " + d.file("sl"));
  ASSERT_EQ(run.code, 0) << run.out;
  EXPECT_EQ(slurp(d.file("one/merged.csv")), slurp(d.file("sl/merged.csv")));
  EXPECT_TRUE(std::filesystem::exists(d.file("sl/job-00005/report.json")));
}

}  // namespace
}  // namespace texsim
