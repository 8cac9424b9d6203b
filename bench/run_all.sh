#!/usr/bin/env bash
# Every benchmark in one command (issue 6): error against time for every scene and estimator with
# Cycles as a peer, the three SMIS applications' own comparisons, speed against Cycles, the cost of
# unused features, export speed and the 1D experiment of the paper's Fig. 2.
#
#   bash bench/run_all.sh --quick   # CI-sized checks (about 10 minutes on 2 cores): small budgets, 1-2 seeds
#   bash bench/run_all.sh           # the full runs behind the README's figures (a few hours on 2 cores)
#
# Results go to bench/results/ (CSV, JSON, PNG, Markdown); the full runs' summaries are the ones
# copied into docs/bench/. Build first (README command 1 or 2); references are cached in
# bench/references/ and rendered when missing.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
PY=/usr/bin/python3   # the system Python: Blender started from another interpreter may not find numpy
BL=(blender -b --factory-startup --addons smis_render)
QUICK=()
[ "${1:-}" = "--quick" ] && QUICK=(--quick)
step() { echo; echo "== $* ($(date +%H:%M:%S))"; }

if [ ${#QUICK[@]} -gt 0 ]; then
    step "equal time, every suite (quick: 2 s budget, 1 seed)"
    $PY bench/equal_time.py --quick --budgets 2
    step "path-space filtering at equal samples (Fig. 6)"
    $PY bench/psf_fig6.py --seeds 1
    step "spectral rendering"
    $PY bench/spectral_bench.py --quick
    step "photon planes"
    "${BL[@]}" --python bench/planes_bench.py -- --quick
    step "many lights (ReSTIR)"
    $PY bench/restir_bench.py --quick
    step "path-space filtering cost against image size"
    $PY bench/psf_cost.py --sizes 256 512 --iterations 2 --out bench/results/psf_cost_quick.md
    step "unused features"
    $PY bench/skip_bench.py --quick
    # Fig. 2 is checked by ctest (engine/tests/mis_fig2_test.cpp); its plot is only redrawn in full.
else
    step "equal time, every suite"
    $PY bench/equal_time.py
    step "path-space filtering at equal samples (Fig. 6)"
    $PY bench/psf_fig6.py
    step "spectral rendering"
    $PY bench/spectral_bench.py
    step "photon planes"
    "${BL[@]}" --python bench/planes_bench.py
    step "path-space filtering cost against image size (256^2 and 1024^2)"
    $PY bench/psf_cost.py
    step "many lights (ReSTIR)"
    $PY bench/restir_bench.py
    step "unused features (time, then instruction counts)"
    $PY bench/skip_bench.py
    $PY bench/skip_bench.py --instructions
    step "paths per second against Cycles"
    "${BL[@]}" --python bench/path_speed.py -- scenes/cornell.blend 256
    step "export speed"
    "${BL[@]}" --python bench/export_bench.py
    step "Fig. 2"
    $PY bench/fig2/fig2.py
fi
step "done: bench/results/"
