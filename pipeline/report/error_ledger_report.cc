#include "pipeline/report/error_ledger_report.h"

#include <cstdio>

#include "pipeline/report/number_text.h"

namespace texsim {

namespace {

nlohmann::ordered_json delta_json(const LedgerDelta& d) {
  return {{"psnr_db", d.psnr_db},
          {"nmse", d.nmse},
          {"dpsnr_db", d.dpsnr_db},
          {"dnmse", d.dnmse},
          {"pixels_changed", d.pixels_changed},
          {"pixels_changed_pct", d.pixels_changed_pct},
          {"dcycles", d.dcycles}};
}

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

}  // namespace

nlohmann::ordered_json ledger_json(const ErrorLedger& l) {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  for (const LedgerRow& r : l.rows) {
    j[r.block] = {
        {"exact", r.exact}, {"materials", r.materials},     {"ops", r.ops},
        {"area", r.area},   {"alone", delta_json(r.alone)}, {"all_but", delta_json(r.all_but)}};
  }
  return j;
}

nlohmann::ordered_json ledger_setup_json(const ErrorLedger& l) {
  return {{"hardware", {{"psnr_db", l.hw_psnr_db}, {"nmse", l.hw_nmse}, {"cycles", l.hw_cycles}}},
          {"all_exact",
           {{"psnr_db", l.exact_psnr_db}, {"nmse", l.exact_nmse}, {"cycles", l.exact_cycles}}},
          {"pixels", l.pixels},
          {"change_threshold", l.change_threshold},
          {"maps", l.maps}};
}

void ledger_markdown(std::ostream& md, const ErrorLedger& l) {
  md << "\n## Error ledger: each block's share of the error\n\n"
     << "Hardware run: PSNR " << fmt(l.hw_psnr_db) << " dB, NMSE " << fmt(l.hw_nmse) << ", "
     << l.hw_cycles << " cycles. Every block below exact: PSNR " << fmt(l.exact_psnr_db)
     << " dB, NMSE " << fmt(l.exact_nmse) << ", " << l.exact_cycles
     << " cycles (the rest is the filter's own error). *Alone*: only this block exact, against "
        "the hardware run; *all but*: every other block exact, against the all-exact run. "
        "ΔPSNR and ΔNMSE are the accuracy the block costs; pixels: covered pixels whose "
        "max-channel error moves by more than "
     << fmt(l.change_threshold) << " (of " << l.pixels
     << "); Δcycles: cycles with the exact block minus without.\n\n"
     << "| block | exact | materials | ops | area | alone ΔPSNR (dB) | alone ΔNMSE | alone "
        "pixels | alone Δcycles | all-but ΔPSNR (dB) | all-but ΔNMSE | all-but pixels |\n"
     << "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const LedgerRow& r : l.rows) {
    md << "| " << r.block << " | " << r.exact << " | " << joined(r.materials) << " | " << r.ops
       << " | " << fmt(r.area) << " | " << fmt(r.alone.dpsnr_db) << " | " << fmt(r.alone.dnmse)
       << " | " << r.alone.pixels_changed << " (" << fmt(r.alone.pixels_changed_pct, 3) << " %) | "
       << r.alone.dcycles << " | " << fmt(r.all_but.dpsnr_db) << " | " << fmt(r.all_but.dnmse)
       << " | " << r.all_but.pixels_changed << " (" << fmt(r.all_but.pixels_changed_pct, 3)
       << " %) |\n";
  }
  if (!l.maps.empty()) {
    md << "\nError maps (how much each block, made exact alone, changes each pixel): "
       << joined(l.maps) << ".\n";
  }
}

}  // namespace texsim
