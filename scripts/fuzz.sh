#!/usr/bin/env bash
# scripts/fuzz.sh - fuzzes the scenario and motor-file parser and the CAN
# command parser (tests/fuzz/fuzz_can_parse.cpp, a third of the scenario
# parser's time, seed corpus tests/fuzz/can_corpus), each for a bounded
# time: builds tests/fuzz/fuzz_scenario.cpp with Clang, libFuzzer,
# AddressSanitizer and UndefinedBehaviorSanitizer (CMake option MC_FUZZ) and
# runs it from the seed corpus tests/fuzz/corpus. With two cores the
# scenario parser's time is split: one process on one core for two thirds
# of it, and on the other core the CAN parser, then a second scenario
# process for the last third that starts from the first one's corpus so far.
# Fails on a crash, a sanitizer report, a leak, an input that takes over
# 10 s, an exception other than ScenarioError or an error message of more
# than one line. Called by .ci/run after test_all.sh; docs/testing.md,
# "Static analysis and fuzzing".
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"

usage() {
    cat <<'EOF'
usage: scripts/fuzz.sh [--time SECONDS] [--build-dir DIR] [-- LIBFUZZER_OPTION...]

Builds the fuzzers (DIR, default build/fuzz) and runs the scenario parser's
for SECONDS (default 60, or $MC_FUZZ_SECONDS) from the seed corpus
tests/fuzz/corpus (with two cores: two processes, 2/3 and 1/3 of it), and
the CAN command parser's for a third of that from tests/fuzz/can_corpus;
the inputs they add go to DIR/run-NAME/corpus, a crashing one to
DIR/run-NAME/crash-*. Exit status 1 if any found anything, 2 on a usage or
build error.

Reproduce a crash:  DIR/tests/fuzz/TARGET DIR/run-NAME/crash-... (NAME: scenario,
                    scenario2 or can; TARGET: fuzz_scenario or fuzz_can_parse)
  --time SECONDS   fuzzing time (libFuzzer -max_total_time)
  --build-dir DIR  build directory of the MC_FUZZ configure
  -h, --help       this text
EOF
}

build="$ROOT/build/fuzz"
seconds="${MC_FUZZ_SECONDS:-60}"
extra=()
while [ $# -gt 0 ]; do
    case "$1" in
        --time) seconds="${2:?--time needs seconds}"; shift ;;
        --build-dir) build="$(realpath -m "${2:?--build-dir needs a directory}")"; shift ;;
        --) shift; extra=("$@"); break ;;
        -h | --help) usage; exit 0 ;;
        *) echo "fuzz.sh: unknown option '$1'" >&2; usage >&2; exit 2 ;;
    esac
    shift
done
[[ "$seconds" =~ ^[0-9]+$ ]] || { echo "fuzz.sh: --time must be a whole number of seconds" >&2; exit 2; }
for t in clang clang++; do
    command -v "$t" >/dev/null 2>&1 || { echo "fuzz.sh: $t not found (scripts/setup.sh installs it)" >&2; exit 2; }
done

t0=$SECONDS
log="$(mktemp)"
trap 'rm -f "$log"' EXIT
# -O1 -g without NDEBUG: the usual fuzzing build (fast, asserts on).
echo "==== fuzz: configure and build $build (clang, -fsanitize=fuzzer,address,undefined)"
if ! cmake -S "$ROOT" -B "$build" -G Ninja -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
    -DCMAKE_BUILD_TYPE=Debug -DCMAKE_C_FLAGS=-O1 -DCMAKE_CXX_FLAGS=-O1 -DMC_FUZZ=ON >"$log" 2>&1 ||
    ! cmake --build "$build" --target fuzz_scenario fuzz_can_parse >>"$log" 2>&1; then
    cat "$log" >&2
    echo "fuzz.sh: configuring or building the fuzzer failed" >&2
    exit 2
fi
echo "---- fuzz: built in $((SECONDS - t0)) s"

# Each run starts from the seed corpus alone, so a failure reproduces from
# its crash file; the harness's files (the input, the motor files) live in
# run/work.
# run_fuzzer NAME TARGET SEED_CORPUS SECONDS MAX_LEN LABEL [MORE_CORPUS...]
# (MORE_CORPUS: read at the start too, e.g. another process's corpus)
run_fuzzer() {
    local name="$1" target="$2" seeds="$3" secs="$4" max_len="$5" label="$6"
    shift 6
    local more=("$@")
    local run="$build/run-$name"
    rm -rf "$run"
    mkdir -p "$run/corpus" "$run/work"
    local n_seeds tf rc=0
    n_seeds=$(find "$seeds" -type f | wc -l)
    echo "==== fuzz: $label, ${secs} s, $n_seeds seed inputs ($seeds)"
    tf=$SECONDS
    MC_FUZZ_WORKDIR="$run/work" \
        ASAN_OPTIONS="detect_leaks=1${ASAN_OPTIONS:+:$ASAN_OPTIONS}" \
        UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}" \
        "$build/tests/fuzz/$target" -max_total_time="$secs" -timeout=10 -rss_limit_mb=2048 -max_len="$max_len" \
        -print_final_stats=1 -artifact_prefix="$run/" "${extra[@]}" "$run/corpus" "$seeds" "${more[@]}" \
        >"$run/fuzz.log" 2>&1 || rc=$?
    # libFuzzer's last status line: "#213389 DONE cov: 2076 ft: 5691 corp: 343/148Kb ..."
    local status execs rate seed cov corp
    status=$(grep -E '^#[0-9]+[[:space:]]+(DONE|pulse|NEW|REDUCE|INITED)' "$run/fuzz.log" | tail -1 || true)
    execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$run/fuzz.log")
    rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$run/fuzz.log")
    seed=$(sed -n 's/^INFO: Seed: *//p' "$run/fuzz.log" | head -1)
    cov=$(sed -n 's/.* cov: \([0-9]*\).*/\1/p' <<<"$status")
    corp=$(sed -n 's/.* corp: \([0-9]*\/[0-9A-Za-z]*\).*/\1/p' <<<"$status")
    echo "---- fuzz: ${execs:-?} inputs in $((SECONDS - tf)) s (${rate:-?}/s), coverage ${cov:-?} edges," \
        "corpus ${corp:-?} (seeds + $(find "$run/corpus" -type f | wc -l) new), libFuzzer -seed=${seed:-?}"
    if [ "$rc" -ne 0 ]; then
        tail -n 60 "$run/fuzz.log"
        echo
        echo "==== fuzz: $target FAILED (libFuzzer exit status $rc); whole log: $run/fuzz.log"
        for c in "$run"/crash-* "$run"/leak-* "$run"/timeout-* "$run"/oom-*; do
            [ -e "$c" ] && echo "  reproduce: $build/tests/fuzz/$target $c"
        done
        return 1
    fi
    rm -rf "$run/work"
    return 0
}

failed=0
can_secs=$(( (seconds + 2) / 3 ))
can_args=(can fuzz_can_parse tests/fuzz/can_corpus "$can_secs" 240 "CAN command parser")
if [ "$(nproc 2>/dev/null || echo 1)" -ge 2 ] && [ "$seconds" -ge 3 ]; then
    # libFuzzer runs one process: with two cores, core 1 runs the scenario
    # parser for 2/3 of its time; core 2 the CAN parser (1/3), then the
    # scenario parser again for the last 1/3, from the seeds and what the
    # first process has found by then. Reports printed in order at the end.
    s1=$(( seconds - seconds / 3 ))
    s2=$(( seconds / 3 ))
    run_fuzzer scenario fuzz_scenario tests/fuzz/corpus "$s1" 8192 "scenario + motor-file parser (1 of 2)" \
        >"$build/report-scenario.txt" 2>&1 &
    pid_scenario=$!
    { run_fuzzer "${can_args[@]}" && rc_can=0 || rc_can=$?
      run_fuzzer scenario2 fuzz_scenario tests/fuzz/corpus "$s2" 8192 "scenario + motor-file parser (2 of 2, from the seeds and the corpus of 1)" \
          "$build/run-scenario/corpus" || rc_can=1
      exit "$rc_can"; } >"$build/report-can.txt" 2>&1 &
    pid_can=$!
    wait "$pid_scenario" || failed=1
    wait "$pid_can" || failed=1
    cat "$build/report-scenario.txt" "$build/report-can.txt"
else
    run_fuzzer scenario fuzz_scenario tests/fuzz/corpus "$seconds" 8192 "scenario + motor-file parser" || failed=1
    run_fuzzer "${can_args[@]}" || failed=1
fi
if [ "$failed" -ne 0 ]; then
    exit 1
fi
echo "==== fuzz: clean ($((SECONDS - t0)) s in all)"
