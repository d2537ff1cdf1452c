#!/usr/bin/env bash
# The installed enact as a lab meets it (issue 52): `cmake --install` of this build into a
# temporary prefix, then, from a folder of one's own with only PREFIX/bin and the system's on
# PATH and nothing of the source or build tree on the way:
#   1. every runnable block of README.md (the tour), docs/getting-started.md and
#      docs/scenes-and-models.md (scripts/run_doc_examples.py --installed);
#   2. an own scene (docs/scenes-and-models.md, "Your own scene"): checked, simulated offline,
#      launched live with its own hand path, recorded, replayed identically;
#   3. a simulated-time experiment on it (an experiment file of one's own naming the shipped
#      trial graph), and the shipped quick experiment's replicates, then the analysis and the
#      power script run as the commands enact printed (the installed scripts);
#   4. the example plugin built by a standalone CMake project with find_package(enact), then
#      loaded by the installed enact-rt in a graph and replayed by the installed enact resim;
#   5. a file found nowhere: the error lists where it looked; the hints name installed paths.
# usage: installed_tour.sh BUILD_DIR SOURCE_DIR [CMAKE]   (ctest: InstalledTour)
set -euo pipefail
build=$(cd "$1" && pwd)
source=$(cd "$2" && pwd)
cmake=${3:-cmake}
work=$(mktemp -d /tmp/enact-installed-tour.XXXXXX)
trap 'rm -rf "$work"' EXIT
prefix=$work/prefix
mine=$work/mine
mkdir -p "$mine" "$work/home" "$work/registry"

step() { printf '\n== %s\n' "$*"; }
fail() { printf 'installed_tour.sh: FAILED: %s\n' "$*" >&2; exit 1; }
# "$1" must hold the line "$2" (a fixed string)
holds() { grep -qF -- "$2" <<<"$1" || fail "expected \"$2\" in:"$'\n'"$1"; }

step "install into $prefix"
"$cmake" --install "$build" --prefix "$prefix" >/dev/null

# the installed tool only, from a folder of one's own
export PATH="$prefix/bin:/usr/bin:/bin" HOME="$work/home" ENACT_REGISTRY="$work/registry"
cd "$mine"
[ "$(command -v enact)" = "$prefix/bin/enact" ] || fail "enact on PATH is $(command -v enact)"

step "1. the README's tour, getting-started, scenes-and-models: their runnable blocks"
/usr/bin/python3 "$source/scripts/run_doc_examples.py" --root "$source" --installed "$prefix" \
  README.md docs/getting-started.md docs/scenes-and-models.md

step "2. an own scene, from check to a replayed recording"
share=$(enact share)
[ "$share" = "$prefix/share/enact" ] || fail "enact share says $share"
sed 's/^scene: two_boxes/scene: my_boxes/' "$(enact share launch/scenes/two_boxes.yaml)" >my_boxes.yaml
# down onto the left box, across the gap, onto the right one
cat >press.csv <<'CSV'
t_s,x_m,y_m,z_m
0,-0.012,0.003,0.0115
0.3,-0.012,0.003,0.0095
0.8,0.015,0.003,0.0095
1.2,0.015,0.003,0.0095
CSV
out=$(enact check my_boxes.yaml)
holds "$out" "my_boxes"
enact simulate my_boxes.yaml --input press.csv --model all
enact launch launch/bridge_rt.yaml --arg scene=my_boxes.yaml --arg hand_path=press.csv --arg observers=1 --duration 1 >launch.log 2>&1 &
launcher=$!
enact record -o mine.mcap
wait "$launcher" || { cat launch.log; fail "enact launch with my_boxes.yaml"; }
holds "$(cat launch.log)" "--param=sim.scene=my_boxes.yaml"
holds "$(cat launch.log)" "rt: the hand felt: mean |F|"
out=$(enact resim mine.mcap)
holds "$out" "identical"

step "3. a simulated-time experiment of one's own, the analysis and the power script as enact prints them"
# graph: found in enact's share (not beside this file); the scene: this folder's
cat >my_experiment.yaml <<'YAML'
name: my_boxes
subjects: 3
virtual_subject: $(share)/launch/experiments/subjects/quick.yaml
conditions: [CM0, CM1]
limit_s: 2
graph: launch/experiments/trial_rt.yaml
launch_args: {scene: "$(dirname)/my_boxes.yaml"}
YAML
enact experiment my_experiment.yaml --clock simulated --out own 2>&1 | tee own.log
holds "$(cat own.log)" "6 trials run"
analysis=$(sed -n 's/^analysis: //p' own.log)
holds "$analysis" "/usr/bin/python3 $prefix/share/enact/scripts/analyze.py own/results.csv --out own/analysis"
eval "$analysis"
[ -f own/analysis/report.md ] || fail "the analysis wrote no own/analysis/report.md"
enact experiment launch/experiments/bridge_quick.yaml --clock simulated --replicates 2 --subjects 3 --conditions CM0,CM1 --out power 2>&1 | tee power.log
hint=$(sed -n 's/.*; power: //p' power.log)
holds "$hint" "/usr/bin/python3 $prefix/share/enact/scripts/power.py power"
out=$(eval "$hint --subjects 3 --step 1 --draws 50")
holds "$out" "subjects"
[ -f power/power/power.csv ] || fail "the power script wrote no power/power/power.csv"

step "4. the example plugin, built against the installed enact with find_package(enact), loaded by it"
"$cmake" -S "$(enact share examples/plugins)" -B plugin -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_TYPE=Release >/dev/null
"$cmake" --build plugin >/dev/null
[ -f plugin/libenact_guide_spring.so ] || fail "no plugin/libenact_guide_spring.so"
out=$(enact-rt --library=plugin/libenact_guide_spring.so --help)
holds "$out" "stiffness_n_per_m"
cat >guided.yaml <<'YAML'
launch:
  - container:
      name: rt
      required: true
      component:
        - {name: sim, plugin: sim, param: [{name: scene, value: "$(share)/launch/scenes/bridge.yaml"}]}
        - {name: ffd, plugin: ffd, param: [{name: start_scene, value: "$(share)/launch/scenes/bridge.yaml"}]}
        - {name: tactile, plugin: tactile}
        - name: guide
          plugin: guide_spring
          library: "$(dirname)/plugin/libenact_guide_spring.so"
          param: [{name: anchor_m, value: "0.0006,-0.0223,0.013"}, {name: stiffness_n_per_m, value: "150"}]
        - {name: rec, plugin: logger, param: [{name: output, value: "$(dirname)/guided.mcap"}]}
YAML
enact launch guided.yaml --clock simulated --duration 1 >guided.log 2>&1 || { cat guided.log; fail "the guided graph"; }
out=$(enact resim guided.mcap)
holds "$out" "stage guide (plugin guide_spring, $mine/plugin/libenact_guide_spring.so) stepped after the model at every tick"
holds "$out" "identical"

step "5. a file found nowhere says where it looked; the hints name what is installed"
if out=$(enact check launch/scenes/nowhere.yaml 2>&1); then fail "enact check of a missing scene exited 0"; fi
holds "$out" "launch/scenes/nowhere.yaml: cannot open the file"
holds "$out" "looked in $mine/launch/scenes/nowhere.yaml (the current directory)"
holds "$out" "looked in $prefix/share/enact/launch/scenes/nowhere.yaml (the installed share)"
out=$(enact --help)
holds "$out" "$prefix/share/doc/enact/scenes-and-models.md"
[ -f "$prefix/share/doc/enact/scenes-and-models.md" ] || fail "the docs are not installed"
out=$(enact devices --profiles)
holds "$out" "$prefix/share/doc/enact/devices.md"
[ "$(enact share core/node/loop_component.h)" = "$prefix/include/enact/core/node/loop_component.h" ] || fail "the plugin header is not installed"
[ "$(enact share docs/components.md)" = "$prefix/share/doc/enact/components.md" ] || fail "the docs are not installed"
for script in analyze psychophysics power agreement graph_deadlines make_ridge plot_bench attach_example; do
  out=$(enact share "scripts/$script.py")
  [ -x "$out" ] || fail "scripts/$script.py: $out is not an installed program"
done
printf '\ninstalled_tour.sh: every step passed\n'
