#pragma once
// The per-block error ledger of a run (`texsim run --ledger`, docs/ledger.md): each block's
// share of the image error, measured by replacing the block with its exact reference, next to
// what the block costs. The runs are made in pipeline/app/error_ledger.cc; this file holds the
// figures and writes them into report.json (`ledger.<block>`) and report.md.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

namespace texsim {

// One comparison of two runs that differ in the exactness of some blocks.
struct LedgerDelta {
  double psnr_db = 0;  // PSNR of the run with the change
  double nmse = 0;
  double dpsnr_db = 0;          // accuracy the block costs (dB): > 0 when the block's error hurts
  double dnmse = 0;             // NMSE the block adds
  uint64_t pixels_changed = 0;  // covered pixels whose error moves by more than the threshold
  double pixels_changed_pct = 0;
  int64_t dcycles = 0;  // cycles of the run with the exact block minus the run without
};

struct LedgerRow {
  std::string block;  // "coords", "derivs", "lod", "subtexel", "vd", "filter_arith", "texels"
  std::string exact;  // what replaced it
  std::vector<std::string> materials;  // materials that have the block
  uint64_t ops = 0;                    // the block's operations over the hardware run
  double area = 0;                     // the block's area (adder-equivalents)
  LedgerDelta alone;                   // only this block exact, against the hardware run
  LedgerDelta all_but;                 // every block exact but this one, against the all-exact run
};

struct ErrorLedger {
  double hw_psnr_db = 0, hw_nmse = 0;  // the run as configured
  uint64_t hw_cycles = 0;
  double exact_psnr_db = 0, exact_nmse = 0;  // every block of the ledger exact
  uint64_t exact_cycles = 0;
  uint64_t pixels = 0;            // covered pixels compared
  double change_threshold = 0;    // per-pixel error change that counts as "changed"
  std::vector<LedgerRow> rows;    // in the ledger's block order
  std::vector<std::string> maps;  // error maps written (file names), with --ledger-maps
  bool empty() const { return rows.empty(); }
};

// The report.json entries: {"<block>": {...}, ...} for `ledger`, and `ledger_setup`.
nlohmann::ordered_json ledger_json(const ErrorLedger& l);
nlohmann::ordered_json ledger_setup_json(const ErrorLedger& l);
// The report.md section.
void ledger_markdown(std::ostream& md, const ErrorLedger& l);

}  // namespace texsim
