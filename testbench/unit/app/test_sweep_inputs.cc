// Hostile input to `texsim sweep` and `texsim merge`: the Slurm script quotes every value and
// cannot be given extra directives, grids too large to count are refused, sweep files and
// merged JSON go through the checked reader, --shard and --job are parsed strictly, and merge
// checks what it reads (depth, types, ranges), escapes its Markdown, refuses a directory given
// twice and waits for a busy ledger.
#include <gtest/gtest.h>
#include <sqlite3.h>
#include <sys/stat.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "blocks/base/input_error.h"
#include "blocks/base/shell_quote.h"
#include "pipeline/app/results_ledger.h"
#include "pipeline/app/sweep.h"
#include "testbench/lib/cli_harness.h"
#include "testbench/lib/error_of.h"
#include "testbench/lib/temp_dir.h"

namespace texsim {
namespace {

namespace fs = std::filesystem;
using cli_harness::shell;
using cli_harness::slurp;

const char* kSweep =
    "[sweep]\nscenes = [\"default\"]\n[grid]\n\"output.width\" = [40, 48]\n"
    "\"pipeline.fifo_depth\" = [2, 4]\n";

// A stub for texsim that writes its arguments, NUL-separated, to $ARGV_FILE.
std::string write_stub(const std::string& path) {
  std::ofstream(path) << "#!/bin/bash\nprintf '%s\\0' \"$@\" > \"$ARGV_FILE\"\n";
  fs::permissions(path, fs::perms::owner_all);
  return path;
}

// Changes the current directory for a scope.
struct InDirectory {
  explicit InDirectory(const fs::path& d) : old(fs::current_path()) { fs::current_path(d); }
  ~InDirectory() { fs::current_path(old); }
  InDirectory(const InDirectory&) = delete;
  InDirectory& operator=(const InDirectory&) = delete;
  fs::path old;
};

// A sweep.sbatch for a sweep file, a texsim and an output directory whose names are shell
// injections: run by bash (the #SBATCH lines are comments to it), the stub gets exactly the
// intended arguments and nothing else runs. The --out given relative is written absolute, so
// the task may start anywhere.
TEST(SweepInputs, SlurmScriptQuotesEveryValueAndRunsNothingElse) {
  TempDir d("sweep_inputs");
  const std::string injection = "q'$(touch PWNED)' `touch PWNED` $HOME 100%";
  const std::string in = injection + " \"x\" \\ \n#SBATCH --wrap='touch PWNED'\n";
  fs::create_directories(d.file(in));
  std::ofstream(d.file(in + "/s.toml")) << kSweep;
  SweepOptions opt;
  opt.slurm = true;
  opt.out = "out " + injection;  // relative to the current directory
  opt.command = write_stub(d.file(in + "/texsim stub"));
  std::ostringstream log;
  {
    const InDirectory here(d.file(""));
    ASSERT_EQ(run_sweep(in + "/s.toml", opt, log), 0) << log.str();
  }
  const std::string out = d.file(opt.out), script = slurp(out + "/sweep.sbatch");
  std::istringstream lines(script);
  std::string line;
  int directives = 0;
  // sbatch reads directives up to the first line that is neither a comment nor blank.
  while (std::getline(lines, line) && (line.empty() || line[0] == '#'))
    directives += line.rfind("#SBATCH", 0) == 0 ? 1 : 0;
  EXPECT_EQ(directives, 4) << script;
  EXPECT_EQ(line.rfind("exec '", 0), 0u) << script;
  EXPECT_NE(script.find("#SBATCH --output=\"" + out + "%/slurm-%A_%a.log\"\n"), std::string::npos)
      << script;
  std::string command = "cd / && SLURM_ARRAY_TASK_ID=3 ARGV_FILE=";
  command.append(shell_quote(d.file("argv"))).append(" bash ");
  command.append(shell_quote(out + "/sweep.sbatch"));
  const auto r = shell(command);
  ASSERT_EQ(r.code, 0) << r.out;
  const std::string expected = std::string("sweep\0", 6) + d.file(in + "/s.toml") + '\0' + "--out" +
                               '\0' + out + '\0' + "--job" + '\0' + "3" + '\0';
  EXPECT_EQ(slurp(d.file("argv")), expected);
  EXPECT_FALSE(fs::exists(d.file("PWNED")));
  EXPECT_FALSE(fs::exists("/PWNED"));
  EXPECT_FALSE(fs::exists("PWNED"));
}

// A line break in the output directory would start a new #SBATCH line: refused, no script.
TEST(SweepInputs, SlurmOutputDirWithALineBreakIsRefused) {
  TempDir d("sweep_inputs");
  std::ofstream(d.file("s.toml")) << kSweep;
  for (const char* name : {"a\n#SBATCH --wrap=touch PWNED\n", "a\r#SBATCH", "a\"b", "a\\b"}) {
    SweepOptions opt;
    opt.slurm = true;
    opt.out = d.file(name);
    opt.command = "/bin/true";
    std::ostringstream log;
    const std::string e = error_of([&] { run_sweep(d.file("s.toml"), opt, log); });
    EXPECT_NE(e.find("cannot be written into the #SBATCH --output line"), std::string::npos) << e;
    EXPECT_FALSE(fs::exists(opt.out + "/sweep.sbatch"));
  }
}

std::string grid_of(int axes, int values) {
  std::string t = "[sweep]\nscenes = [\"default\"]\n[grid]\n";
  for (int a = 0; a < axes; ++a) {
    t += "\"k" + std::to_string(a) + "\" = [";
    for (int v = 0; v < values; ++v) t += (v ? ", " : "") + std::to_string(v);
    t += "]\n";
  }
  return t;
}

// 2^64 jobs used to wrap to 0 and write --array=0-18446744073709551615.
TEST(SweepInputs, JobCountIsCheckedForOverflowAndLimited) {
  TempDir d("sweep_inputs");
  const auto load_error = [&](const std::string& text) {
    std::ofstream(d.file("s.toml")) << text;
    return error_of([&] { (void)load_sweep(d.file("s.toml")); });
  };
  const std::string f = d.file("s.toml");
  EXPECT_EQ(load_error(grid_of(64, 2)),
            f + ": the sweep has more than 100000 jobs, the limit (1 input(s) x 64 grid axes; "
                "docs/cli.md#input-limits)");
  EXPECT_NE(load_error(grid_of(17, 2)).find("more than 100000 jobs"), std::string::npos);
  EXPECT_EQ(load_error(grid_of(1, 100001)),
            f + ": grid.k0: more than 100000 values, the job limit");
  EXPECT_EQ(load_error(grid_of(1, 100000)), "");
  // A long value times many jobs: refused before the jobs are made.
  EXPECT_NE(load_error(grid_of(1, 300) + "\"long\" = [\"" + std::string(1 << 20, 'x') + "\"]\n")
                .find("MiB of job inputs and overrides"),
            std::string::npos);
  SweepOptions opt;
  opt.slurm = true;
  opt.out = d.file("o");
  opt.command = "/bin/true";
  std::ofstream(d.file("s.toml")) << grid_of(64, 2);
  std::ostringstream log;
  EXPECT_THROW(run_sweep(d.file("s.toml"), opt, log), InputError);
  EXPECT_FALSE(fs::exists(d.file("o/sweep.sbatch")));
}

// A directory, a FIFO or /dev/zero as the sweep file: a clear error at once.
TEST(SweepInputs, SweepFileMustBeARegularFile) {
  TempDir d("sweep_inputs");
  ASSERT_EQ(::mkfifo(d.file("fifo").c_str(), 0600), 0);
  for (const std::string& p : {d.file(""), d.file("fifo"), std::string("/dev/zero")}) {
    const std::string e = error_of([&] { (void)load_sweep(p); });
    EXPECT_NE(e.find("sweep file"), std::string::npos) << p << ": " << e;
  }
}

TEST(SweepInputs, ShardAndJobAreParsedStrictly) {
  int k = 0, n = 0;
  parse_sweep_shard("2/3", k, n);
  EXPECT_EQ(k, 2);
  EXPECT_EQ(n, 3);
  parse_sweep_shard("1/1", k, n);
  EXPECT_EQ(n, 1);
  for (const char* bad : {"1/2/3", "1.5/2", "0/0", "0/2", "3/2", "1/0", "1", "/", "", " 1/2",
                          "1/2 ", "+1/2", "-1/2", "1/-2", "1/2x", "1/99999999999999999999"}) {
    EXPECT_EQ(error_of([&] { parse_sweep_shard(bad, k, n); }),
              "--shard " + std::string(bad) +
                  ": expected K/N, two whole numbers with 1 <= K <= N (for example 2/4)")
        << bad;
  }
  EXPECT_EQ(parse_sweep_job("0"), 0);
  EXPECT_EQ(parse_sweep_job("17"), 17);
  for (const char* bad : {"-1", "1.5", "x", "", "+3", "4294967296", "3 "}) {
    EXPECT_NE(error_of([&] {
                (void)parse_sweep_job(bad);
              }).find(": expected a job number, a whole number from 0"),
              std::string::npos)
        << bad;
  }
}

// The command line: --job -1 and --shard 1/2/3 are usage errors with the messages above (exit 2).
TEST(SweepInputs, CliRefusesNegativeJobAndLaxShard) {
  TempDir d("sweep_inputs");
  std::ofstream(d.file("s.toml")) << kSweep;
  const std::string bin = TEXSIM_BINARY, s = shell_quote(d.file("s.toml"));
  auto r = shell(bin + " sweep " + s + " --job -1 --out " + shell_quote(d.file("o")));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("--job -1: expected a job number"), std::string::npos) << r.out;
  r = shell(bin + " sweep " + s + " --shard 1/2/3 --out " + shell_quote(d.file("o")));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("--shard 1/2/3: expected K/N"), std::string::npos) << r.out;
}

const char* kJob = R"({"job": 0, "scene": "default", "trace": "", "overrides": ["a=1"]})";
const char* kReport =
    R"({"fragments": 10, "cycles": 100, "cycles_per_fragment": 10.0, "accuracy": {"psnr_db": 30.5}})";

// A sweep output directory DIR with job-00000/job.json and report.json.
void write_job(const TempDir& d, const std::string& dir, const std::string& job,
               const std::string& report) {
  fs::create_directories(d.file(dir + "/job-00000"));
  std::ofstream(d.file(dir + "/job-00000/job.json")) << job;
  std::ofstream(d.file(dir + "/job-00000/report.json")) << report;
}

std::string merge_error(const TempDir& d, const std::string& job, const std::string& report) {
  fs::remove_all(d.file("in"));
  write_job(d, "in", job, report);
  std::ostringstream log;
  return error_of([&] { merge_sweeps({d.file("in")}, d.file("m"), log, false); });
}

TEST(SweepInputs, MergeChecksDepthAndTypes) {
  TempDir d("sweep_inputs");
  const std::string rf = d.file("in/job-00000/report.json"), jf = d.file("in/job-00000/job.json");
  EXPECT_EQ(merge_error(d, kJob, kReport), "");
  // 100,000 levels used to overflow the stack.
  EXPECT_EQ(merge_error(d, kJob, std::string(100000, '[') + std::string(100000, ']')),
            rf + ": JSON nested deeper than 64 levels (byte 64)");
  EXPECT_EQ(merge_error(
                d, kJob,
                "{\"a\": \"[[[[[[\", \"b\": " + std::string(63, '[') + std::string(63, ']') + "}"),
            "");  // brackets in strings do not count; 64 levels are fine
  EXPECT_EQ(merge_error(d, R"({"job": 0, "overrides": 5})", kReport),
            jf + ": overrides: expected an array of strings");
  EXPECT_EQ(merge_error(d, R"({"job": 0, "overrides": [1]})", kReport),
            jf + ": overrides: expected an array of strings");
  EXPECT_EQ(merge_error(d, R"({"job": "0"})", kReport), jf + ": job: expected an integer");
  EXPECT_EQ(merge_error(d, "[1]", kReport), jf + ": the file: expected a JSON object");
  EXPECT_EQ(merge_error(d, kJob, R"({"cycles": "many"})"), rf + ": cycles: expected a number");
  EXPECT_EQ(merge_error(d, kJob, R"({"accuracy": [1]})"),
            rf + ": /accuracy: expected a JSON object");
  EXPECT_EQ(merge_error(d, kJob, R"({"provenance": {"command": 3}})"),
            rf + ": provenance/command: expected a string");
  EXPECT_NE(merge_error(d, kJob, "{").find(rf + ": not a valid JSON file"), std::string::npos);
}

TEST(SweepInputs, MergeInputsMustBeRegularFiles) {
  TempDir d("sweep_inputs");
  write_job(d, "in", kJob, kReport);
  fs::remove(d.file("in/job-00000/report.json"));
  fs::create_directory(d.file("in/job-00000/report.json"));
  std::ostringstream log;
  std::string e = error_of([&] { merge_sweeps({d.file("in")}, d.file("m"), log, false); });
  EXPECT_NE(e.find("report.json"), std::string::npos) << e;
  EXPECT_NE(e.find("directory"), std::string::npos) << e;
  fs::remove(d.file("in/job-00000/report.json"));
  ASSERT_EQ(::mkfifo(d.file("in/job-00000/report.json").c_str(), 0600), 0);
  e = error_of([&] { merge_sweeps({d.file("in")}, d.file("m"), log, false); });
  EXPECT_NE(e.find("report.json"), std::string::npos) << e;
}

TEST(SweepInputs, MergeRefusesTheSameDirectoryTwice) {
  TempDir d("sweep_inputs");
  write_job(d, "in", kJob, kReport);
  std::ostringstream log;
  EXPECT_EQ(error_of([&] {
              merge_sweeps({d.file("in"), d.file("in/../in/.")}, d.file("m"), log, false);
            }),
            d.file("in/../in/.") + ": given twice (the same directory as " + d.file("in") + ")");
  EXPECT_FALSE(fs::exists(d.file("m/merged.csv")));
}

// Markdown cells: '|' escaped and line breaks made spaces, so each row keeps its 13 cells.
TEST(SweepInputs, MergeMarkdownEscapesPipesAndLineBreaks) {
  TempDir d("sweep_inputs");
  write_job(d, "in",
            R"({"job": 0, "scene": "a|b\nc\\", "trace": "", "overrides": ["x=|", "y=\r\n"]})",
            kReport);
  std::ostringstream log;
  ASSERT_EQ(merge_sweeps({d.file("in")}, d.file("m"), log, false), 1);
  const std::string md = slurp(d.file("m/merged.md"));
  EXPECT_NE(md.find("| 0 | a\\|b c\\\\ |  | x=\\|; y=   | 10 | 100 |"), std::string::npos) << md;
  std::istringstream lines(md);
  std::string line;
  int rows = 0;
  while (std::getline(lines, line)) rows += line.rfind('|', 0) == 0 ? 1 : 0;
  EXPECT_EQ(rows, 3);  // header, rule, one job
  EXPECT_NE(slurp(d.file("m/merged.csv")).find("\"a|b\nc\\\""), std::string::npos);
}

// cycles = 2^64 - 1 used to be stored as -1.
TEST(SweepInputs, LedgerStoresIntegersBeyondInt64AsReal) {
  TempDir d("sweep_inputs");
  write_job(d, "in", kJob, R"({"fragments": 1, "cycles": 18446744073709551615})");
  std::ostringstream log;
  ASSERT_EQ(merge_sweeps({d.file("in")}, d.file("m"), log, false), 1);
  EXPECT_NE(slurp(d.file("m/merged.csv")).find(",18446744073709551615,"), std::string::npos);
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(d.file("m/ledger.sqlite").c_str(), &db), SQLITE_OK);
  sqlite3_stmt* st = nullptr;
  ASSERT_EQ(sqlite3_prepare_v2(db, "SELECT typeof(cycles), cycles, fragments FROM runs", -1, &st,
                               nullptr),
            SQLITE_OK);
  ASSERT_EQ(sqlite3_step(st), SQLITE_ROW);
  EXPECT_STREQ(reinterpret_cast<const char*>(sqlite3_column_text(st, 0)), "real");
  EXPECT_DOUBLE_EQ(sqlite3_column_double(st, 1), 18446744073709551615.0);
  EXPECT_EQ(sqlite3_column_int64(st, 2), 1);
  sqlite3_finalize(st);
  sqlite3_close(db);
}

// Another connection holds the database locked for a moment: the ledger waits for it
// (busy timeout) instead of failing with "database is locked".
TEST(SweepInputs, LedgerWaitsForAnotherWriter) {
  TempDir d("sweep_inputs");
  const std::string path = d.file("ledger.sqlite");
  ResultsLedger ledger(path);
  sqlite3* other = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &other), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(other, "BEGIN EXCLUSIVE", nullptr, nullptr, nullptr), SQLITE_OK);
  std::thread release([other] {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    sqlite3_exec(other, "COMMIT", nullptr, nullptr, nullptr);
  });
  const auto job = nlohmann::ordered_json::parse(kJob);
  const auto report = nlohmann::ordered_json::parse(kReport);
  bool added = false;
  EXPECT_EQ(error_of([&] { added = ledger.add(job, report, "abc"); }), "");
  release.join();
  sqlite3_close(other);
  EXPECT_TRUE(added);
  EXPECT_EQ(ledger.rows(), 1);
}

}  // namespace
}  // namespace texsim
