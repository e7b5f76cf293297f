#!/usr/bin/env python3
"""Runs a shell job inside a VM on Debian's own kernel (the VM fixture,
tools/vm/README.md): qemu-system-x86_64 with TCG boots the kernel and
initramfs of tools/vm/build_image.py; the host's root filesystem is the
VM's, read-only, except one writable folder (--share, default the
repository), so the job uses the project's binaries and venv as they are.
The job runs as root in the VM, where vcan and comedi_test are loaded.

    tools/vm/vm_run.py [--share DIR] [--timeout S] [--mem MB] -- 'shell job'

The job's output streams to stdout; the exit status is the job's. 77 when
the fixture cannot run here (no qemu-system-x86_64, no kernel image: the
message names it), 124 on timeout, 125 when the VM did not report a status
(a kernel panic, or init failed: the console is printed).
"""
import argparse
import os
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
SKIP = 77
QEMU = "qemu-system-x86_64"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--share", default=ROOT, help="writable folder in the VM, at the same path (default: the repository)")
    ap.add_argument("--image", default=os.path.join(ROOT, "build", "vm"), help="folder of vmlinuz and initramfs.img")
    ap.add_argument("--timeout", type=float, default=600.0, help="seconds before the VM is killed (default 600)")
    ap.add_argument("--mem", type=int, default=1024, help="VM memory in MiB (default 1024)")
    ap.add_argument("job", nargs=argparse.REMAINDER, help="-- then the shell job")
    a = ap.parse_args()
    job = a.job[1:] if a.job[:1] == ["--"] else a.job
    if not job:
        ap.error("no job given (-- 'commands')")
    if not (a.timeout > 0):
        ap.error("--timeout must be > 0")
    qemu = shutil.which(QEMU)
    if qemu is None:
        print(f"vm_run: {QEMU} not found (apt-get install qemu-system-x86)", file=sys.stderr)
        return SKIP
    r = subprocess.run([sys.executable, os.path.join(HERE, "build_image.py"), "--out", a.image],
                       stdout=subprocess.DEVNULL)
    if r.returncode != 0:
        return r.returncode
    share = os.path.realpath(a.share)
    if not os.path.isdir(share):
        ap.error(f"--share: {share} is not a folder")
    jobs = os.path.join(share, "build", "vm", "jobs")
    os.makedirs(jobs, exist_ok=True)
    with tempfile.TemporaryDirectory(dir=jobs, prefix="job.") as jd:
        with open(os.path.join(jd, "job.sh"), "w") as f:
            f.write("set -e\ncd " + sh_quote(os.getcwd()) + "\n" + " ".join(job) + "\n")
        cmd = [qemu, "-accel", "tcg", "-cpu", "max", "-m", str(a.mem), "-smp", "1", "-nodefaults", "-no-user-config",
               "-display", "none", "-serial", "stdio", "-no-reboot",
               "-kernel", os.path.join(a.image, "vmlinuz"), "-initrd", os.path.join(a.image, "initramfs.img"),
               "-append", f"console=ttyS0 quiet loglevel=3 panic=-1 vm_share={share} vm_job={jd}",
               "-virtfs", "local,path=/,mount_tag=hostroot,security_model=none,readonly=on,multidevs=remap",
               "-virtfs", f"local,path={share},mount_tag=share,security_model=none,multidevs=remap"]
        try:
            p = subprocess.run(cmd, stdin=subprocess.DEVNULL, timeout=a.timeout)
        except subprocess.TimeoutExpired:
            print(f"vm_run: the VM ran past --timeout {a.timeout:g} s and was killed", file=sys.stderr)
            return 124
        status = os.path.join(jd, "status")
        if not os.path.exists(status):
            print(f"vm_run: the VM exited ({p.returncode}) without the job's status: it did not boot or init failed",
                  file=sys.stderr)
            return 125
        return int(open(status).read().strip() or 125)


def sh_quote(s):
    return "'" + s.replace("'", "'\\''") + "'"


if __name__ == "__main__":
    sys.exit(main())
