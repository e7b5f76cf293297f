#!/usr/bin/env bash
# scripts/check_static.sh - static analysis of the host code; any finding
# fails it. Called by .ci/run after test_all.sh.
#
#   cppcheck     firmware/ (C11) in float and in fixed point, sim/ and
#                sim/model/hal_sw_plant (C++17) in both, hal/backends/mcu (C11,
#                32-bit, as the Cortex-M4F float and Cortex-M3 fixed images)
#   clang-tidy   the checks of .clang-tidy, through the compile_commands.json
#                of a host configure: firmware/ in float and in fixed point,
#                sim/ (with the software plant backend) in float. The Clang
#                static analyzer (clang-analyzer-*) runs on firmware/ always
#                and on sim/ only with --full (docs/testing.md: why)
#   clang-format the style of .clang-format (clang-format --dry-run -Werror)
#                on the C and C++ files of firmware/, hal/, sim/, design/ and
#                tools/ but the generated ones and those of
#                scripts/clang_format_pending.txt, a list that may only shrink
#
# Check sets and why: .clang-tidy and docs/testing.md ("Static analysis and
# fuzzing"). Suppressions are inline only, each with its reason:
# "cppcheck-suppress ID ; why" and "NOLINT(check): why".
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"

usage() {
    cat <<'EOF'
usage: scripts/check_static.sh [--build-dir DIR] [--jobs N] [--full] [cppcheck] [clang-tidy] [clang-format]

Runs cppcheck and clang-tidy over firmware/, sim/ and hal/, and clang-format's
check of .clang-format over firmware/, hal/, sim/, design/ and tools/ (default:
all three); exits 1 on any finding, 2 on a usage or set-up error.

  --build-dir DIR  where the host configures for compile_commands.json go
                   (DIR/float, DIR/fixed; default build/static)
  --jobs N         parallel clang-tidy and cppcheck processes (default: nproc)
  --full           the Clang static analyzer on sim/ too (CI: on firmware/
                   only; on sim/ it doubles clang-tidy's time)
  -h, --help       this text
EOF
}

build="$ROOT/build/static"
jobs="$(nproc 2>/dev/null || echo 2)"
tools=()
full=0
while [ $# -gt 0 ]; do
    case "$1" in
        --build-dir) build="$(realpath -m "${2:?--build-dir needs a directory}")"; shift ;;
        --jobs) jobs="${2:?--jobs needs a number}"; shift ;;
        --full) full=1 ;;
        cppcheck | clang-tidy | clang-format) tools+=("$1") ;;
        -h | --help) usage; exit 0 ;;
        -*) echo "check_static.sh: unknown option '$1'" >&2; usage >&2; exit 2 ;;
        *) echo "check_static.sh: unknown tool '$1' (cppcheck, clang-tidy or clang-format)" >&2; usage >&2; exit 2 ;;
    esac
    shift
done
[ "${#tools[@]}" -gt 0 ] || tools=(cppcheck clang-tidy clang-format)
want() { printf '%s\n' "${tools[@]}" | grep -qx -- "$1"; }

for t in "${tools[@]}"; do
    command -v "$t" >/dev/null 2>&1 || {
        echo "check_static.sh: $t not found (scripts/setup.sh installs it)" >&2
        exit 2
    }
done

t0=$SECONDS
failed=()

# Host configures (no build needed: the generated headers come from the
# configure step) that give clang-tidy its compile commands.
configure() {
    local dir="$build/$1" fixed="$2" log
    log="$(mktemp)"
    if ! cmake -S "$ROOT" -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=Release -DMC_FIXED_POINT="$fixed" \
        -DCMAKE_EXPORT_COMPILE_COMMANDS=ON >"$log" 2>&1; then
        cat "$log" >&2
        rm -f "$log"
        echo "check_static.sh: configuring $dir failed" >&2
        exit 2
    fi
    rm -f "$log"
}
if want cppcheck || want clang-tidy; then
    echo "==== static: configure $build/{float,fixed} (compile_commands.json)"
    configure float OFF
    configure fixed ON
fi
gen="$build/float/firmware/generated"

# ------------------------------------------------------------ cppcheck ----
CPPCHECK=(cppcheck --enable=warning,style,performance,portability --inline-suppr --error-exitcode=1 -q
          --template=gcc -j "$jobs" --suppress=useStlAlgorithm -I firmware -I hal/include -I "$gen")
run_cppcheck() {  # NAME ARGS...
    local name="$1"
    shift
    echo "---- cppcheck: $name"
    if ! "${CPPCHECK[@]}" "$@"; then
        failed+=("cppcheck: $name")
    fi
}
if want cppcheck; then
    tc=$SECONDS
    echo "==== static: $(cppcheck --version), --enable=warning,style,performance,portability"
    for fx in 0 1; do
        cfg=$([ $fx = 1 ] && echo "fixed point" || echo float)
        run_cppcheck "firmware/ (C11, $cfg)" --std=c11 -DMC_FIXED_POINT=$fx firmware
        run_cppcheck "sim/ (C++17, $cfg)" --std=c++17 --language=c++ -DMC_FIXED_POINT=$fx \
            -I sim -I sim/model -I "$build/float/sim" sim
    done
    # The Cortex-M images: 32-bit, the macros of each target (mc_num_fixed.h's
    # assembly on the M3); the PIL image (its pil_drive.h is generated per
    # drive by CMake: not found here) and every drive's own PIL probe.
    m4f=(--std=c11 --platform=unix32 -I hal/backends/mcu -DMC_FIXED_POINT=0 -D__arm__ -D__ARM_ARCH_7EM__ -D__ARM_FP=4)
    m3=(--std=c11 --platform=unix32 -I hal/backends/mcu -DMC_FIXED_POINT=1 -D__arm__ -D__ARM_ARCH_7M__)
    mcu=(hal/backends/mcu/mcu_rt.c hal/backends/mcu/mcu_semihost.c hal/backends/mcu/selftest.c
         hal/backends/mcu/pil_image.c hal/backends/mcu/pil_probe_none.c)
    run_cppcheck "hal/backends/mcu (C11, Cortex-M4F float)" "${m4f[@]}" "${mcu[@]}"
    run_cppcheck "tools/bench/pil_probes (C11, Cortex-M4F float)" "${m4f[@]}" tools/bench/pil_probes/*.c
    # the image's drive is a configure-time option (MC_DRIVE): checked with
    # the stm32f405 preset's
    run_cppcheck "hal/backends/stm32f405 (C11, Cortex-M4F float)" "${m4f[@]}" -I hal/backends/stm32f405 \
        -I hal/include -I firmware -I . -DMC_DRIVE_NAME=\"paper001\" -DMC_DRIVE_OPS=paper001_drive_ops \
        -DMC_DESIGN_OPS=paper001_design_ops -DMC_BOARD_PARAMS=board_params_vesc6 \
        hal/backends/stm32f405/*.c hal/backends/stm32f405/boards/*.c
    run_cppcheck "hal/backends/mcu (C11, Cortex-M3 fixed point)" "${m3[@]}" "${mcu[@]}"
    run_cppcheck "tools/bench/pil_probes (C11, Cortex-M3 fixed point)" "${m3[@]}" tools/bench/pil_probes/*.c
    echo "---- cppcheck: $((SECONDS - tc)) s"
fi

# ---------------------------------------------------------- clang-tidy ----
# The translation units of DIR/compile_commands.json under the given source
# directories (the tests and tools are not checked), one per line: the C++
# units first, larger files first (a unit takes 2-35 s, a C unit about 1 s),
# so that the long ones do not start last and leave a core idle at the end.
units() {  # DIR PREFIX...
    local db="$1/compile_commands.json"
    shift
    python3 - "$db" "$ROOT" "$@" <<'EOF'
import json, os, sys
db, root, prefixes = sys.argv[1], sys.argv[2], sys.argv[3:]
seen = []
for e in json.load(open(db)):
    f = os.path.normpath(os.path.join(e["directory"], e["file"]))
    rel = os.path.relpath(f, root)
    if any(rel.startswith(p) for p in prefixes) and f not in seen:
        seen.append(f)
seen.sort(key=lambda f: (not f.endswith(".cpp"), -os.path.getsize(f)))
print("\n".join(seen))
EOF
}
# One clang-tidy per unit, JOBS at a time, over lines "DIR CHECKS FILE"
# (CHECKS: all, or noanalyzer: .clang-tidy's checks but clang-analyzer-*);
# each unit's output printed whole. One list for all passes, sorted again as a
# whole, so the long units of one pass do not leave a core idle at the end of
# another.
tidy_list=""
tidy_names=()
add_tidy() {  # NAME DIR CHECKS PREFIX...
    local name="$1" dir="$2" checks="$3" list
    shift 3
    list="$(units "$dir" "$@")"
    echo "---- clang-tidy: $name ($(wc -l <<<"$list") units$([ "$checks" = all ] || echo ", without clang-analyzer-*"))"
    tidy_list+="$(sed "s|^|$dir $checks |" <<<"$list")"$'\n'
    tidy_names+=("$name")
}
run_tidy() {
    local rc=0
    # shellcheck disable=SC2016
    grep -v '^$' <<<"$tidy_list" | python3 -c '
import os, sys
rows = [l.split(" ", 2) for l in sys.stdin.read().splitlines()]
rows.sort(key=lambda r: (not r[2].endswith(".cpp"), -os.path.getsize(r[2])))
print("\n".join(" ".join(r) for r in rows))' |
        xargs -P "$jobs" -L1 sh -c 'set -f; c=""; [ "$2" = all ] || c="--checks=-clang-analyzer-*";
        out=$(clang-tidy -p "$1" --quiet $c "$3" 2>&1); rc=$?;
        out=$(printf "%s\n" "$out" | grep -Ev "^[0-9]+ warnings? (and [0-9]+ errors? )?generated\.$");
        if [ $rc -ne 0 ] || [ -n "$out" ]; then printf "%s\n" "$out"; fi
        [ $rc -eq 0 ] || echo "clang-tidy: FAILED: $3"; exit $rc' sh || rc=$?
    [ "$rc" -eq 0 ] || failed+=("clang-tidy: one of ${tidy_names[*]}")
}
if want clang-tidy; then
    tt=$SECONDS
    n_checks=$(clang-tidy -p "$build/float" --list-checks firmware/model/motor_model.c 2>/dev/null | grep -c '^    ' || true)
    echo "==== static: clang-tidy $(clang-tidy --version | sed -n 's/.*LLVM version //p' | head -1), $n_checks checks (.clang-tidy)"
    sim_checks=noanalyzer
    [ "$full" = 0 ] || sim_checks=all
    add_tidy "firmware/ (float)" "$build/float" all firmware/
    add_tidy "sim/ (float)" "$build/float" "$sim_checks" sim/
    add_tidy "firmware/ (fixed point)" "$build/fixed" all firmware/
    run_tidy
    echo "---- clang-tidy: $((SECONDS - tt)) s"
fi

# -------------------------------------------------------- clang-format ----
# .clang-format at the root is the style the code already follows (tuned on
# clang-format 14, Debian 12's). Every C and C++ file of the trees below
# must conform, but the generated ones and those listed in
# scripts/clang_format_pending.txt: a ratchet (as PENDING of
# tools/checks/drive_names.py), which may only shrink. A listed file that
# conforms now, or no longer exists, fails too (take it off the list).
FORMAT_PENDING=scripts/clang_format_pending.txt
format_files() {  # the checked files, generated ones left out
    find firmware hal sim design tools -type f \( -name '*.c' -o -name '*.h' -o -name '*.cpp' -o -name '*.hpp' \) \
        ! -path 'firmware/comm/generated/*' ! -path 'firmware/drives/*/boards/*_params.c' \
        ! -path 'firmware/drives/*/generated/*' ! -path 'firmware/config/generated/*' | LC_ALL=C sort
}
if want clang-format; then
    tf=$SECONDS
    echo "==== static: $(clang-format --version | sed 's/^.*clang-format version/clang-format/' | head -1), .clang-format"
    mapfile -t pending < <(grep -Ev '^[[:space:]]*(#|$)' "$FORMAT_PENDING")
    declare -A is_pending=()
    stale=()
    for f in "${pending[@]}"; do
        is_pending[$f]=1
        if [ ! -f "$f" ]; then
            stale+=("$f: does not exist")
        elif clang-format --dry-run -Werror "$f" >/dev/null 2>&1; then
            stale+=("$f: conforms now")
        fi
    done
    conform=()
    while IFS= read -r f; do
        [ -n "${is_pending[$f]:-}" ] || conform+=("$f")
    done < <(format_files)
    echo "---- clang-format: ${#conform[@]} files conform, ${#pending[@]} not yet ($FORMAT_PENDING)"
    if ! clang-format --dry-run -Werror "${conform[@]}"; then
        failed+=("clang-format: files not in the style of .clang-format, not in $FORMAT_PENDING (above)")
    fi
    if [ "${#stale[@]}" -gt 0 ]; then
        printf '%s\n' "${stale[@]/%/: take it off $FORMAT_PENDING}"
        failed+=("clang-format: $FORMAT_PENDING lists files it should not (above)")
    fi
    echo "---- clang-format: $((SECONDS - tf)) s"
fi

echo
if [ "${#failed[@]}" -gt 0 ]; then
    echo "==== static: FAILED ($((SECONDS - t0)) s):"
    printf '  %s\n' "${failed[@]}"
    exit 1
fi
echo "==== static: clean (${tools[*]}; $((SECONDS - t0)) s)"
