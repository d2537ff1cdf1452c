#include "nodes/enact/sweep_report.h"

#include <cstdio>

namespace enact::cli {

void print_sweep(const std::vector<physics::reference::SweepRow>& rows, const char* title) {
  std::printf("\n%s\n%-16s %6s %9s %12s %12s %10s %7s\n", title, "integrator", "kHz", "ns/step", "F rms N", "F max N", "pins diff", "faults");
  for (const physics::reference::SweepRow& r : rows) {
    std::printf("%-16s %6.0f %9.1f %12.3e %12.3e %10.2e %7llu\n", physics::to_string(r.integrator), r.rate_hz / 1e3, r.ns_per_step,
                r.force_rms_error_n, r.force_max_error_n, r.pins_mismatch_fraction, static_cast<unsigned long long>(r.faults));
  }
}

void sweep_json(Json& j, const std::vector<physics::reference::SweepRow>& rows) {
  j.begin_array();
  for (const physics::reference::SweepRow& r : rows) {
    j.begin_object().field("integrator", physics::to_string(r.integrator)).field("rate_hz", r.rate_hz).field("ns_per_step", r.ns_per_step);
    j.field("force_rms_error_n", r.force_rms_error_n).field("force_max_error_n", r.force_max_error_n);
    j.field("pins_mismatch_fraction", r.pins_mismatch_fraction).field("faults", static_cast<long long>(r.faults)).end_object();
  }
  j.end_array();
}

}  // namespace enact::cli
