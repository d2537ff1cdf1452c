#include "nodes/enact-bench/bench_physics_body.h"

#include <cstdio>

#include "core/haptics/computer_model.h"
#include "core/physics/scene.h"
#include "core/sim/offline.h"
#include "nodes/enact/args.h"
#include "nodes/enact/sweep_report.h"

namespace enact::cli {

BodyRows deformable_rows(const std::string& scene, double reference_hz) {
  BodyRows out;
  out.scene = find_file(scene);
  physics::Model m = physics::load_scene(out.scene);
  sim::SimParams p;
  p.scene = out.scene;
  p.force = true;
  sim::Simulator simulator;
  simulator.configure(p);
  const task::Trajectory path = sim::scripted_path(simulator);
  std::fprintf(stderr, "enact bench: the deformable body along its scripted path, 3 integrators x 6 rates against %.0f kHz\n", reference_hz / 1e3);
  const haptics::ComputerModel cm = *haptics::preset("CM1", m.proxies[0].rows * m.proxies[0].cols);
  haptics::apply(cm, m);
  out.rows = physics::reference::rate_sweep(m, [&cm](const physics::Model& model, const physics::State& s) { return haptics::pins(cm, model, s); },
                                            [&path](double t) { return path.at(path.start_s() + t); }, path.end_s() - path.start_s(), reference_hz);
  return out;
}

void print_deformable_rows(const BodyRows& rows) {
  const std::string title = "deformable body (" + rows.scene + ") along its scripted path (CM1), device force against the reference;"
                            " faults: the divergence guard (an explicit scheme past the body's step bound, enact check)";
  print_sweep(rows.rows, title.c_str());
}

void deformable_rows_json(Json& j, const BodyRows& rows) {
  j.key("deformable_rows");
  sweep_json(j, rows.rows);
}

}  // namespace enact::cli
