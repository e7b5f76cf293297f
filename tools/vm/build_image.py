#!/usr/bin/env python3
"""Builds the VM fixture's boot files from Debian packages: Debian's own
kernel (linux-image-amd64, which ships vcan, SocketCAN and the Comedi
driver comedi_test) and a minimal initramfs (busybox-static, the kernel
modules the tests need with their dependencies, an init that mounts the
host's root read-only and one writable folder over 9p, then runs a job in
a chroot of the host). See tools/vm/README.md.

    tools/vm/build_image.py [--out DIR] [--check]

Writes DIR/vmlinuz and DIR/initramfs.img (default build/vm); the kernel
package is downloaded once with `apt-get download` into DIR/cache and
never installed on the host. Standard library only (no cpio, no kmod
needed). Exit 0 done (or up to date), 1 failure, 77 what it needs cannot be
had here (no apt-get download of the kernel, no busybox-static): the
message names it.
"""
import argparse
import fcntl
import gzip
import hashlib
import io
import os
import re
import shutil
import subprocess
import sys
import tarfile
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
META_PACKAGE = "linux-image-amd64"
BUSYBOX = "/bin/busybox"
SKIP = 77

# What the VM loads at boot, in dependency order after resolution: 9p over
# virtio-pci for the host's files, SocketCAN with vcan (the CAN issue),
# Comedi with comedi_test (the DAC/ADC board issue).
MODULES = ["virtio_pci", "9pnet_virtio", "9p", "can", "can-raw", "vcan", "comedi", "comedi_test"]


def die(msg, code=1):
    print(f"build_image: {msg}", file=sys.stderr)
    sys.exit(code)


def kernel_package():
    """The versioned package linux-image-amd64 depends on."""
    try:
        out = subprocess.run(["apt-cache", "depends", META_PACKAGE], capture_output=True, text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError) as e:
        die(f"apt-cache depends {META_PACKAGE}: {e}", SKIP)
    m = re.search(r"Depends:\s*(linux-image-\S+)", out)
    if not m:
        die(f"apt-cache: no kernel package behind {META_PACKAGE} (is the Debian archive in sources.list?)", SKIP)
    return m.group(1)


def download(pkg, cache):
    os.makedirs(cache, exist_ok=True)
    debs = [f for f in os.listdir(cache) if f.startswith(pkg + "_") and f.endswith(".deb")]
    if debs:
        return os.path.join(cache, sorted(debs)[-1])
    r = subprocess.run(["apt-get", "download", pkg], cwd=cache, capture_output=True, text=True)
    debs = [f for f in os.listdir(cache) if f.startswith(pkg + "_") and f.endswith(".deb")]
    if r.returncode != 0 or not debs:
        die(f"apt-get download {pkg} failed: {r.stderr.strip()[-300:]}", SKIP)
    return os.path.join(cache, debs[0])


def extract_deb(deb, dest):
    """dpkg-deb -x without dpkg-deb: ar archive, data.tar.* member."""
    with open(deb, "rb") as f:
        data = f.read()
    if not data.startswith(b"!<arch>\n"):
        die(f"{deb}: not a Debian package")
    pos = 8
    while pos < len(data):
        name = data[pos:pos + 16].decode().strip().rstrip("/")
        size = int(data[pos + 48:pos + 58].decode().strip())
        body = data[pos + 60:pos + 60 + size]
        if name.startswith("data.tar"):
            r = subprocess.run(["dpkg-deb", "-x", deb, dest]) if shutil.which("dpkg-deb") else None
            if r is None or r.returncode != 0:
                with tarfile.open(fileobj=io.BytesIO(body)) as t:
                    t.extractall(dest)
            return
        pos += 60 + size + (size & 1)
    die(f"{deb}: no data member")


def modinfo_depends(path):
    with open(path, "rb") as f:
        blob = f.read()
    m = re.search(rb"\x00depends=([^\x00]*)\x00", blob)
    return [d for d in m.group(1).decode().split(",") if d] if m else []


def resolve(modroot):
    """The modules of MODULES and their dependencies, dependencies first."""
    index = {}
    for dirpath, _, files in os.walk(modroot):
        for fn in files:
            if fn.endswith(".ko"):
                index[fn[:-3].replace("-", "_")] = os.path.join(dirpath, fn)
    order, seen = [], set()
    stack = [(m.replace("-", "_"), False) for m in reversed(MODULES)]
    while stack:  # iterative depth-first post-order (no recursion)
        name, expanded = stack.pop()
        if expanded:
            if name not in seen:
                seen.add(name)
                order.append(name)
            continue
        if name in seen:
            continue
        if name not in index:
            die(f"kernel module {name} is not in the kernel package (built in?)")
        stack.append((name, True))
        for dep in reversed(modinfo_depends(index[name])):
            dep = dep.replace("-", "_")
            if dep not in seen:
                stack.append((dep, False))
    return [(n, index[n]) for n in order]


INIT = r"""#!/bin/busybox sh
# init of the VM fixture (tools/vm/build_image.py): modules, the host's root
# read-only and the job's folder writable over 9p, then the job in a chroot.
/bin/busybox --install -s /bin
export PATH=/bin
mount -t proc proc /proc
mount -t sysfs sys /sys
mount -t devtmpfs dev /dev
for m in $(cat /etc/modules.order); do
    insmod /lib/modules/$m.ko || echo "vm-init: insmod $m failed"
done
for a in $(cat /proc/cmdline); do
    case "$a" in
        vm_share=*) SHARE="${a#vm_share=}" ;;
        vm_job=*) JOB="${a#vm_job=}" ;;
    esac
done
H=/host
mkdir -p $H
mount -t 9p -o trans=virtio,version=9p2000.L,ro,msize=262144,cache=loose hostroot $H || echo "vm-init: host root not mounted"
mount -t proc proc $H/proc
mount -t sysfs sys $H/sys
mount -t devtmpfs dev $H/dev
mkdir -p $H/dev/shm $H/dev/pts 2>/dev/null
mount -t tmpfs shm $H/dev/shm
mount -t tmpfs tmp $H/tmp
mount -t tmpfs run $H/run
mount -t tmpfs root $H/root
# the shared folder last: a folder under /tmp is made in the VM's tmpfs
mkdir -p $H$SHARE 2>/dev/null
mount -t 9p -o trans=virtio,version=9p2000.L,msize=262144 share $H$SHARE || echo "vm-init: $SHARE not mounted"
echo "vm-init: running $JOB/job.sh"
chroot $H /usr/bin/env -i HOME=/tmp PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin \
    LANG=C.UTF-8 /bin/sh "$JOB/job.sh" < /dev/console > /dev/console 2>&1
echo $? > $H$JOB/status
sync
umount $H$SHARE 2>/dev/null
poweroff -f
"""


def cpio_newc(entries):
    """entries: (path, mode, data or None for directories, link target or None)."""
    out = io.BytesIO()
    ino = 1
    for path, mode, data, link in entries + [("TRAILER!!!", 0, b"", None)]:
        body = link.encode() if link is not None else (data or b"")
        name = path.encode() + b"\x00"
        hdr = "070701" + "".join(f"{v:08X}" for v in (
            ino, mode, 0, 0, 1, 0, len(body), 0, 0, 0, 0, len(name), 0))
        out.write(hdr.encode() + name)
        out.write(b"\x00" * ((4 - (110 + len(name)) % 4) % 4))
        out.write(body)
        out.write(b"\x00" * ((4 - len(body) % 4) % 4))
        ino += 1
    return out.getvalue()


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default=os.path.join(ROOT, "build", "vm"))
    args = ap.parse_args()
    if not os.path.exists(BUSYBOX):
        die(f"{BUSYBOX} missing: apt-get install busybox-static", SKIP)
    pkg = kernel_package()
    out = os.path.abspath(args.out)
    os.makedirs(out, exist_ok=True)
    # One builder at a time: the VM tests run in parallel under ctest and
    # each asks for the image first; the others wait here and then find it
    # up to date (two writers of initramfs.img.tmp once made a VM boot a
    # half-written image).
    with open(os.path.join(out, "build.lock"), "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        return build(pkg, out)


def build(pkg, out):
    stamp = os.path.join(out, "image.stamp")
    want = hashlib.sha256((pkg + INIT + ",".join(MODULES) + open(__file__).read()).encode()).hexdigest()
    if os.path.exists(stamp) and open(stamp).read() == want and all(
            os.path.exists(os.path.join(out, f)) for f in ("vmlinuz", "initramfs.img")):
        print(f"build_image: {out} up to date ({pkg})")
        return 0
    deb = download(pkg, os.path.join(out, "cache"))
    with tempfile.TemporaryDirectory(dir=out) as tmp:
        extract_deb(deb, tmp)
        boot = os.path.join(tmp, "boot")
        kernels = [f for f in os.listdir(boot) if f.startswith("vmlinuz-")]
        if not kernels:
            die(f"{deb}: no vmlinuz")
        mods = resolve(os.path.join(tmp, "lib", "modules"))
        entries = [(d, 0o40755, None, None) for d in ("bin", "dev", "proc", "sys", "etc", "lib", "lib/modules", "host")]
        entries.append(("bin/busybox", 0o100755, open(BUSYBOX, "rb").read(), None))
        entries.append(("init", 0o100755, INIT.encode(), None))
        entries.append(("etc/modules.order", 0o100644, ("\n".join(n for n, _ in mods) + "\n").encode(), None))
        for name, path in mods:
            entries.append((f"lib/modules/{name}.ko", 0o100644, open(path, "rb").read(), None))
        img = gzip.compress(cpio_newc(entries), compresslevel=6)
        with open(os.path.join(out, "initramfs.img.tmp"), "wb") as f:
            f.write(img)
        shutil.copyfile(os.path.join(boot, kernels[0]), os.path.join(out, "vmlinuz.tmp"))
    os.replace(os.path.join(out, "initramfs.img.tmp"), os.path.join(out, "initramfs.img"))
    os.replace(os.path.join(out, "vmlinuz.tmp"), os.path.join(out, "vmlinuz"))
    with open(stamp, "w") as f:
        f.write(want)
    print(f"build_image: {out}/vmlinuz ({pkg}), initramfs.img ({len(img) // 1024} KiB, modules: "
          f"{' '.join(n for n, _ in mods)})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
