#!/usr/bin/env bash
# scripts/run_paper000.sh - the simulated drive on paper 000's experiment
# (Delpoux & Floquet 2014, section 5): sets up, builds the host preset, runs
# motorsim on sim/scenarios/paper000_experiment.toml. motorsim prints the
# metrics and writes the CSV and PNG into out/paper000_experiment/.
#
# Extra arguments go to motorsim, e.g. ./scripts/run_paper000.sh --seed 3
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"

case "${1:-}" in
    -h | --help)
        cat <<'EOF'
usage: scripts/run_paper000.sh [MOTORSIM_ARGS...]

Installs what is missing (scripts/setup.sh --no-cross), builds the host
preset, then runs
  build/host/sim/motorsim --scenario sim/scenarios/paper000_experiment.toml \
                          --out out/paper000_experiment [MOTORSIM_ARGS...]
which prints the metrics and writes CSV + PNG into out/paper000_experiment/.
EOF
        exit 0 ;;
esac

SCENARIO=sim/scenarios/paper000_experiment.toml
OUT=out/paper000_experiment
MOTORSIM=build/host/sim/motorsim

# The simulator needs no cross toolchain: skip it (scripts/test_all.sh installs it).
scripts/setup.sh --no-cross

echo "== configure + build (preset host)"
cmake --preset host
cmake --build --preset host

[ -x "$MOTORSIM" ] || { echo "run_paper000: $MOTORSIM was not built" >&2; exit 1; }
[ -f "$SCENARIO" ] || { echo "run_paper000: missing $SCENARIO" >&2; exit 1; }

echo "== $MOTORSIM --scenario $SCENARIO --out $OUT $*"
mkdir -p "$OUT"
"$MOTORSIM" --scenario "$SCENARIO" --out "$OUT" "$@"

echo "== outputs in $OUT/:"
ls -1 "$OUT"
