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
usage: scripts/run_paper000.sh [--scenario FILE] [--out DIR] [MOTORSIM_ARGS...]

Installs what is missing (scripts/setup.sh --no-cross), builds the host
preset, then runs
  build/host/sim/motorsim --scenario sim/scenarios/paper000_experiment.toml \
                          --out out/paper000_experiment [MOTORSIM_ARGS...]
which prints the metrics and writes CSV + PNG into out/paper000_experiment/.
--scenario and --out replace the defaults. The exit status is motorsim's
(motorsim --help lists them).
EOF
        exit 0 ;;
esac

SCENARIO=sim/scenarios/paper000_experiment.toml
OUT=out/paper000_experiment
MOTORSIM=build/host/sim/motorsim
# --scenario and --out may be given: they replace the defaults (motorsim
# would refuse them twice); everything else goes to motorsim as it is.
ARGS=()
while [ $# -gt 0 ]; do
    case "$1" in
        --scenario | --out)
            [ $# -ge 2 ] || { echo "run_paper000: $1 needs a value" >&2; exit 2; }
            if [ "$1" = --scenario ]; then SCENARIO=$2; else OUT=$2; fi
            shift 2 ;;
        --scenario=*) SCENARIO=${1#--scenario=}; shift ;;
        --out=*) OUT=${1#--out=}; shift ;;
        *) ARGS+=("$1"); shift ;;
    esac
done
[ -n "$OUT" ] || { echo "run_paper000: --out: empty path" >&2; exit 2; }

scripts/setup.sh --no-cross

echo "== configure + build (preset host)"
cmake --preset host
cmake --build --preset host

[ -x "$MOTORSIM" ] || { echo "run_paper000: $MOTORSIM was not built" >&2; exit 1; }
[ -f "$SCENARIO" ] || { echo "run_paper000: missing $SCENARIO" >&2; exit 1; }

echo "== $MOTORSIM --scenario $SCENARIO --out $OUT ${ARGS[*]}"
rc=0
"$MOTORSIM" --scenario "$SCENARIO" --out "$OUT" "${ARGS[@]}" || rc=$?

if [ -d "$OUT" ]; then
    echo "== outputs in $OUT/:"
    ls -1 "$OUT"
fi
exit $rc
