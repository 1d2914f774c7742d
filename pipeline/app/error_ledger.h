#pragma once
// The per-block error ledger (`texsim run --ledger`, docs/ledger.md): the run is repeated with
// one block at a time replaced by its exact reference (and with every block exact but one),
// through whole-material `--set` overrides, and each block's share of the error is measured
// against the run as configured.
#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

#include "pipeline/app/run.h"
#include "pipeline/report/error_ledger_report.h"

namespace texsim {

struct Scene;

struct LedgerRun {
  ErrorLedger ledger;
  // With opt.ledger_maps: (file name, image with only that block exact), per block.
  std::vector<std::pair<std::string, ImageRgb>> maps;
};

// A block of the ledger and the materials of `scene` that have it (empty: none has it).
struct LedgerBlock {
  std::string name, exact;
  std::vector<std::string> materials;
};
std::vector<LedgerBlock> ledger_blocks(const Scene& scene);

// The overrides that make the blocks in `exact` (bit i = ledger block i) exact in `scene`.
std::vector<std::string> exact_overrides(const Scene& scene, unsigned exact);

// `hw`: the capture of the run as configured (opt without the ledger). Runs the other
// variants without writing files.
LedgerRun run_error_ledger(const RunOptions& opt, const RunCapture& hw, std::ostream& log);

}  // namespace texsim
