#!/usr/bin/env bash
# scripts/test_all.sh - every test: sets up, then for each preset in PRESETS
# configures, builds, and runs ctest when a test preset of that name exists
# (cross presets have none: they are built only). Goes on past a failing
# preset, prints a summary, exits non-zero if anything failed.
# This is what CI runs (.ci/run).
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"

# Presets of CMakePresets.json, in this order. Adding one is a one-line change.
PRESETS=(
    host
    host-fixed
    host-strict
    host-asan
    cortex-m4f
    cortex-m3-fixed
    stm32f405
    stm32f405-paper002-vesc6
    stm32f405-paper002-vesc6-sensorless
    stm32f405-paper000-odrive36
)

usage() {
    cat <<EOF
usage: scripts/test_all.sh [--no-setup] [PRESET...]

For each preset (default: ${PRESETS[*]}): cmake --preset P,
cmake --build --preset P, and ctest --preset P if P has a test preset.

  PRESET...    only these presets (must be in CMakePresets.json)
  --no-setup   do not run scripts/setup.sh first
  -h, --help   this text

Environment: MC_CTEST_TIMEOUT (default 900) seconds per test that sets no
TIMEOUT of its own. ctest logs go to build/test_all/PRESET.ctest.log.
EOF
}

do_setup=1
selected=()
for arg in "$@"; do
    case "$arg" in
        --no-setup) do_setup=0 ;;
        -h | --help) usage; exit 0 ;;
        -*) echo "test_all.sh: unknown option '$arg'" >&2; usage >&2; exit 2 ;;
        *) selected+=("$arg") ;;
    esac
done
[ "${#selected[@]}" -eq 0 ] || PRESETS=("${selected[@]}")

t0=$SECONDS
fmt_time() { printf '%dm%02ds' $(($1 / 60)) $(($1 % 60)); }

# Names listed by 'cmake --list-presets=KIND' (lines like:  "host" - Host build).
list_presets() {
    local out
    out=$(cmake --list-presets="$1" 2>&1) || {
        echo "test_all.sh: 'cmake --list-presets=$1' failed:" >&2
        echo "$out" >&2
        exit 2
    }
    sed -n 's/^ *"\([^"]*\)".*/\1/p' <<<"$out"
}
configure_presets=$(list_presets configure)
build_presets=$(list_presets build)
test_presets=$(list_presets test)
has() { grep -qx -- "$2" <<<"$1"; }

for p in "${PRESETS[@]}"; do
    if ! has "$configure_presets" "$p"; then
        echo "test_all.sh: no configure preset '$p' in CMakePresets.json (have: $(echo $configure_presets))" >&2
        exit 2
    fi
done

LOGDIR="$ROOT/build/test_all"
mkdir -p "$LOGDIR"

# The apt packages first (the builds need them); the venv (pip, mostly
# downloads and unpacking) is installed while the first preset builds, and
# the first ctest waits for it: on a fresh clone that hides most of its
# 35-40 s.
venv_pid=""
venv_log="$LOGDIR/setup_venv.log"
if [ "$do_setup" = 1 ]; then
    scripts/setup.sh --no-venv
    scripts/setup.sh --venv-only >"$venv_log" 2>&1 &
    venv_pid=$!
fi
wait_venv() {
    [ -n "$venv_pid" ] || return 0
    local rc=0
    wait "$venv_pid" || rc=$?
    venv_pid=""
    cat "$venv_log"
    if [ "$rc" -ne 0 ]; then
        echo "test_all.sh: scripts/setup.sh --venv-only failed (exit $rc); log: $venv_log" >&2
        exit 2
    fi
}
ctest_timeout="${MC_CTEST_TIMEOUT:-900}"
failed=0
total_pass=0
total_fail=0
summary=()

for p in "${PRESETS[@]}"; do
    tp=$SECONDS
    status="ok"
    tests="-"
    echo
    echo "==== preset $p: configure"
    if ! cmake --preset "$p"; then
        status="CONFIGURE FAILED"
    else
        echo "==== preset $p: build"
        if ! has "$build_presets" "$p"; then
            echo "test_all.sh: no build preset '$p' in CMakePresets.json" >&2
            status="NO BUILD PRESET"
        elif ! cmake --build --preset "$p"; then
            status="BUILD FAILED"
        elif ! has "$test_presets" "$p"; then
            tests="(build only)"
        else
            wait_venv
            echo "==== preset $p: test"
            log="$LOGDIR/$p.ctest.log"
            rc=0
            ctest --preset "$p" --no-tests=error --timeout "$ctest_timeout" 2>&1 | tee "$log" || rc=$?
            # ctest's closing line: "97% tests passed, 1 tests failed out of 37"
            line=$(grep -E '^[0-9]+% tests passed, [0-9]+ tests? failed out of [0-9]+' "$log" | tail -1 || true)
            if [ -n "$line" ]; then
                nfail=$(sed -E 's/.*passed, ([0-9]+) tests? failed out of ([0-9]+).*/\1/' <<<"$line")
                ntot=$(sed -E 's/.*out of ([0-9]+).*/\1/' <<<"$line")
                total_pass=$((total_pass + ntot - nfail))
                total_fail=$((total_fail + nfail))
                tests="$((ntot - nfail))/$ntot tests passed"
            else
                tests="no ctest summary"
            fi
            [ "$rc" -eq 0 ] || status="TESTS FAILED"
        fi
    fi
    [ "$status" = ok ] || failed=1
    summary+=("$(printf '  %-18s %-18s %-24s %s' "$p" "$status" "$tests" "$(fmt_time $((SECONDS - tp)))")")
done

wait_venv
echo
echo "==== summary ($(fmt_time $((SECONDS - t0))) in all)"
printf '%s\n' "${summary[@]}"
echo "ctest: $total_pass passed, $total_fail failed"
exit "$failed"
