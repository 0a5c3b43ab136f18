#!/usr/bin/python3
"""Worst-case stack of the DTC control path from GCC's -fcallgraph-info=su graphs (.ci files).

usage: stack_report.py ROOT_FUNCTION DIR_WITH_CI_FILES [LIBGCC_A [TARGET_BYTES]]

Each function's own frame comes from the graph ("N bytes (static)"); the worst path from the
root is own frame + the deepest callee chain. Library helpers (__aeabi_*) have no graph node:
their frames are read from the disassembly of libgcc.a (push/sub sp at entry) when given."""
import glob
import os
import re
import subprocess
import sys

root, cidir = sys.argv[1], sys.argv[2]
libgcc = sys.argv[3] if len(sys.argv) > 3 else None
target = int(sys.argv[4]) if len(sys.argv) > 4 else 256

frames, edges, kinds = {}, {}, {}
node_re = re.compile(r'node: \{ title: "([^"]+)" label: "([^"]*)"')
edge_re = re.compile(r'edge: \{ sourcename: "([^"]+)" targetname: "([^"]+)"')
for ci in glob.glob(os.path.join(cidir, "*.ci")):
    for line in open(ci):
        m = node_re.search(line)
        if m:
            title, label = m.group(1), m.group(2)
            fm = re.search(r"(\d+) bytes \((\w+)\)", label)
            if fm:
                frames[title] = int(fm.group(1))
                kinds[title] = fm.group(2)
            continue
        m = edge_re.search(line)
        if m:
            edges.setdefault(m.group(1), set()).add(m.group(2))


def builtin_frame(name):
    """Bytes pushed at entry of a libgcc helper (push {...} and sub sp, #n)."""
    if not libgcc:
        return None
    try:
        dis = subprocess.run(["arm-none-eabi-objdump", "-d", libgcc], capture_output=True,
                             text=True, check=True).stdout
    except Exception:
        return None
    m = re.search(r"<%s>:\n((?:.*\n){1,12})" % re.escape(name), dis)
    if not m:
        return None
    total = 0
    for line in m.group(1).splitlines():
        p = re.search(r"\bpush\s+\{([^}]*)\}", line)
        if p:
            total += 4 * len([r for r in p.group(1).split(",") if r.strip()])
        s = re.search(r"\bsub\s+sp,\s*#(\d+)", line)
        if s:
            total += int(s.group(1))
    return total


builtins = {}


def frame_of(f):
    if f in frames:
        return frames[f]
    if f not in builtins:
        builtins[f] = builtin_frame(f)
    return builtins[f] or 0


def worst(f, seen):
    if f in seen:
        raise SystemExit("recursion through %s" % f)
    best, path = 0, []
    for g in edges.get(f, ()):
        d, p = worst(g, seen | {f})
        if d > best:
            best, path = d, p
    return frame_of(f) + best, [f] + path


total, path = worst(root, set())
print("control-path stack (arm-none-eabi, cortex-m0, -Os, -fstack-usage/-fcallgraph-info):")
for f in path:
    name = f.split(":")[-1]
    src = "libgcc" if f in builtins else kinds.get(f, "?")
    print("  %-28s %4d bytes (%s)" % (name, frame_of(f), src))
print("  worst-case total from %s: %d bytes (target <= %d)" % (root, total, target))
unknown = [b for b, v in builtins.items() if v is None]
if unknown:
    print("  note: frames not found for", ", ".join(unknown), "(counted as 0)")
