#!/usr/bin/env bash
# scripts/setup.sh - installs everything the project needs on Debian 12.
#
#   apt packages   installed only when dpkg says they are missing
#                  ('apt-get update' runs only then)
#   .venv/         Python venv at the repo root from tools/requirements.txt,
#                  reinstalled only when that file changed (sha256 stamp)
#
# Idempotent; when nothing is missing it takes well under a second.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

usage() {
    cat <<'EOF'
usage: scripts/setup.sh [--no-cross] [--no-venv | --venv-only] [--check] [-q|--quiet] [-h|--help]

Installs the project's apt packages and its Python venv (.venv).

  --no-cross   skip the cross toolchain and QEMU (gcc-arm-none-eabi,
               libnewlib-arm-none-eabi, qemu-system-arm)
  --no-venv    the apt packages only
  --venv-only  the venv only (scripts/test_all.sh installs it while the
               first preset builds: the builds do not need it)
  --check      install nothing: list what is missing, exit 1 if anything is
  -q, --quiet  print only errors and what gets installed
  -h, --help   this text

Environment: MC_BASE_PYTHON (default /usr/bin/python3) is the interpreter
the venv is made from.
EOF
}

cross=1
check_only=0
quiet=0
do_apt=1
do_venv=1
for arg in "$@"; do
    case "$arg" in
        --no-cross) cross=0 ;;
        --no-venv) do_venv=0 ;;
        --venv-only) do_apt=0 ;;
        --check) check_only=1 ;;
        -q | --quiet) quiet=1 ;;
        -h | --help) usage; exit 0 ;;
        *) echo "setup.sh: unknown option '$arg'" >&2; usage >&2; exit 2 ;;
    esac
done

[ "$do_apt" = 1 ] || [ "$do_venv" = 1 ] || { echo "setup.sh: --no-venv and --venv-only together install nothing" >&2; exit 2; }

t_start=$(date +%s%N)
say() { [ "$quiet" = 1 ] || echo "setup: $*"; }
die() { echo "setup: error: $*" >&2; exit 1; }

# Host build: compilers, CMake/Ninja, GoogleTest, Eigen (plant), toml++
# (scenarios), CLI11 (command line), python3-venv (the venv below),
# libcomedi (the DAC/ADC board's driver for real cards through Comedi).
BASE_PKGS=(cmake ninja-build gcc g++ googletest libgtest-dev python3-venv
           libeigen3-dev libtomlplusplus-dev libcli11-dev libcomedi-dev)
# Static analysis and fuzzing (scripts/check_static.sh, scripts/fuzz.sh, both
# in CI): cppcheck, clang-tidy, clang-format; clang with libFuzzer and the sanitizer
# runtimes (libclang-rt-14-dev: clang 14 only recommends it, and packages are
# installed here without recommends); llvm for llvm-symbolizer (sanitizer
# reports with file and line).
ANALYSIS_PKGS=(cppcheck clang-tidy clang-format clang libclang-rt-14-dev llvm)
# The VM fixture (tools/vm/: Debian's own kernel in QEMU with TCG, for the
# SocketCAN and Comedi tests this machine's kernel cannot run): QEMU for
# x86-64, busybox-static for the initramfs, can-utils (candump, cansend)
# and iproute2 (ip link add ... type vcan) used inside the VM. The kernel
# package itself is downloaded by tools/vm/build_image.py, never installed.
VM_PKGS=(qemu-system-x86 busybox-static can-utils iproute2)
# Cross builds and processor-in-the-loop runs.
CROSS_PKGS=(gcc-arm-none-eabi libnewlib-arm-none-eabi qemu-system-arm)

PKGS=("${BASE_PKGS[@]}" "${ANALYSIS_PKGS[@]}" "${VM_PKGS[@]}")
[ "$cross" = 1 ] && PKGS+=("${CROSS_PKGS[@]}")

# Only one setup at a time (two terminals, or parallel scripts).
mkdir -p "$ROOT/build"
exec 9>"$ROOT/build/.setup.lock"
if command -v flock >/dev/null 2>&1; then
    flock -w 900 9 || die "another scripts/setup.sh holds $ROOT/build/.setup.lock"
fi

# Prints the packages among "$@" that dpkg does not list as installed.
missing_pkgs() {
    local installed
    installed=$(dpkg-query -W -f='${Package} ${db:Status-Abbrev}\n' "$@" 2>/dev/null |
        awk '$2 == "ii" { print $1 }' || true)
    local p
    for p in "$@"; do
        grep -qx -- "$p" <<<"$installed" || echo "$p"
    done
}

# ---------------------------------------------------------------- apt ----
todo=0
if [ "$do_apt" = 0 ]; then
    say "apt: skipped (--venv-only)"
elif command -v dpkg-query >/dev/null 2>&1; then
    mapfile -t missing < <(missing_pkgs "${PKGS[@]}")
    if [ "${#missing[@]}" -eq 0 ]; then
        say "apt: all ${#PKGS[@]} packages present"
    elif [ "$check_only" = 1 ]; then
        echo "setup: apt: missing: ${missing[*]}"
        todo=1
    else
        SUDO=()
        if [ "$(id -u)" -ne 0 ]; then
            command -v sudo >/dev/null 2>&1 || die "not root and no sudo: install ${missing[*]} yourself"
            if [ -t 0 ]; then SUDO=(sudo); else SUDO=(sudo -n); fi
        fi
        echo "setup: apt: installing ${missing[*]}"
        APT_OPTS=(-o DPkg::Lock::Timeout=300 -o Dpkg::Use-Pty=0)
        "${SUDO[@]}" apt-get "${APT_OPTS[@]}" -q update
        "${SUDO[@]}" env DEBIAN_FRONTEND=noninteractive \
            apt-get "${APT_OPTS[@]}" -q install -y --no-install-recommends "${missing[@]}"
        mapfile -t still < <(missing_pkgs "${missing[@]}")
        [ "${#still[@]}" -eq 0 ] || die "apt: still missing after install: ${still[*]}"
    fi
else
    echo "setup: warning: no dpkg-query (not Debian?): make sure these are installed: ${PKGS[*]}" >&2
fi

# --------------------------------------------------------------- venv ----
if [ "$do_venv" = 0 ]; then
    say "venv: skipped (--no-venv)"
else
    BASE_PY="${MC_BASE_PYTHON:-/usr/bin/python3}"
    VENV="$ROOT/.venv"
    REQ="$ROOT/tools/requirements.txt"
    STAMP="$VENV/.requirements.stamp"
    [ -f "$REQ" ] || die "missing $REQ"
    # The stamp names the requirements' content and the base interpreter.
    want="$(sha256sum "$REQ" | cut -d' ' -f1) $BASE_PY"
    have="$(cat "$STAMP" 2>/dev/null || true)"

    venv_ok=0
    if [ -x "$VENV/bin/python" ] && "$VENV/bin/python" -c '' 2>/dev/null; then venv_ok=1; fi

    if [ "$venv_ok" = 1 ] && [ "$have" = "$want" ]; then
        say "venv: up to date ($VENV)"
    elif [ "$check_only" = 1 ]; then
        if [ "$venv_ok" = 0 ]; then echo "setup: venv: missing or broken: $VENV"
        else echo "setup: venv: tools/requirements.txt changed since the last install"; fi
        todo=1
    else
        [ -x "$BASE_PY" ] || die "no $BASE_PY (set MC_BASE_PYTHON)"
        if [ "$venv_ok" = 0 ]; then
            echo "setup: venv: creating $VENV with $BASE_PY"
            rm -rf "$VENV"
            "$BASE_PY" -m venv "$VENV" || die "venv creation failed (is python3-venv installed?)"
        fi
        echo "setup: venv: installing tools/requirements.txt"
        rm -f "$STAMP"
        # --no-compile: Python writes the bytecode of the modules it imports
        # when it first imports them, instead of pip compiling every module
        # of every package here (half of pip's CPU time: 27 s -> 14 s)
        PIP_NO_INPUT=1 "$VENV/bin/python" -m pip install --disable-pip-version-check --no-compile -q -r "$REQ" ||
            die "pip install -r tools/requirements.txt failed"
        echo "$want" >"$STAMP"
    fi
fi

t_ms=$(( ($(date +%s%N) - t_start) / 1000000 ))
if [ "$check_only" = 1 ]; then
    if [ "$todo" = 1 ]; then echo "setup: check: something is missing (run scripts/setup.sh)"; exit 1; fi
    say "check: nothing missing (${t_ms} ms)"
else
    say "done in ${t_ms} ms"
fi
