#!/usr/bin/python3
"""Worst-case stack of the DTC control path from GCC's -fcallgraph-info=su graphs (.ci files).

usage: stack_report.py ROOT_FUNCTION DIR_WITH_CI_FILES [LIBGCC_A [TARGET_BYTES]]

Each function's own frame comes from the graph ("N bytes (static)"); the worst path from the
root is own frame + the deepest callee chain. Library helpers (__aeabi_*) have no graph node:
their frames are read from the disassembly of libgcc.a (push/sub sp at entry) when given.
A call through a pointer (gcc's "__indirect_call" node) is not followed: Graph.indirect lists
the functions that make one. Also used by hal/f2812/stack_budget.py (class Graph)."""
import glob
import os
import re
import subprocess
import sys

NODE_RE = re.compile(r'node: \{ title: "([^"]+)" label: "([^"]*)"')
EDGE_RE = re.compile(r'edge: \{ sourcename: "([^"]+)" targetname: "([^"]+)"')


class Graph:
    def __init__(self, cidir, libgcc=None):
        self.libgcc = libgcc
        self.frames, self.edges, self.kinds, self.builtins = {}, {}, {}, {}
        self.indirect = set()
        self._dis = None
        for ci in glob.glob(os.path.join(cidir, "*.ci")):
            for line in open(ci):
                m = NODE_RE.search(line)
                if m:
                    title, label = m.group(1), m.group(2)
                    fm = re.search(r"(\d+) bytes \((\w+)\)", label)
                    if fm:
                        self.frames[title] = int(fm.group(1))
                        self.kinds[title] = fm.group(2)
                    continue
                m = EDGE_RE.search(line)
                if m:
                    if m.group(2) == "__indirect_call":
                        self.indirect.add(m.group(1).split(":")[-1])
                    else:
                        self.edges.setdefault(m.group(1), set()).add(m.group(2))

    def builtin_frame(self, name):
        """Bytes pushed at entry of a libgcc helper (push {...} and sub sp, #n)."""
        if not self.libgcc:
            return None
        if self._dis is None:
            try:
                self._dis = subprocess.run(["arm-none-eabi-objdump", "-d", self.libgcc],
                                           capture_output=True, text=True, check=True).stdout
            except Exception:
                self._dis = ""
        m = re.search(r"<%s>:\n((?:.*\n){1,12})" % re.escape(name), self._dis)
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

    def frame_of(self, f):
        if f in self.frames:
            return self.frames[f]
        if f not in self.builtins:
            self.builtins[f] = self.builtin_frame(f)
        return self.builtins[f] or 0

    def title(self, name):
        """The node of a function by its name (an external one's title is its name, a static
        one's FILE:name)."""
        if name in self.frames:
            return name
        t = [k for k in self.frames if k.split(":")[-1] == name]
        if len(t) != 1:
            raise SystemExit("stack_report: %d functions named %s" % (len(t), name))
        return t[0]

    def frame_named(self, name):
        """The frame of a function by its name (a libgcc helper's from its disassembly)."""
        if name in self.frames or not any(k.split(":")[-1] == name for k in self.frames):
            return self.frame_of(name)
        return self.frame_of(self.title(name))

    def callees(self, name):
        """The names of the functions a function calls directly."""
        return sorted(f.split(":")[-1] for f in self.edges.get(self.title(name), ()))

    def worst(self, f, seen=frozenset()):
        """(bytes, path of titles) of the deepest chain from node f."""
        if f in seen:
            raise SystemExit("recursion through %s" % f)
        best, path = 0, []
        for g in self.edges.get(f, ()):
            d, p = self.worst(g, seen | {f})
            if d > best:
                best, path = d, p
        return self.frame_of(f) + best, [f] + path

    def worst_named(self, name):
        """As worst(), from a function's name; the path as names."""
        total, path = self.worst(self.title(name))
        return total, path

    def unknown(self):
        return sorted(b for b, v in self.builtins.items() if v is None)


def main():
    root, cidir = sys.argv[1], sys.argv[2]
    libgcc = sys.argv[3] if len(sys.argv) > 3 else None
    target = int(sys.argv[4]) if len(sys.argv) > 4 else 256
    g = Graph(cidir, libgcc)
    total, path = g.worst(root)
    print("control-path stack (arm-none-eabi, cortex-m0, -Os, -fstack-usage/-fcallgraph-info):")
    for f in path:
        name = f.split(":")[-1]
        src = "libgcc" if f in g.builtins else g.kinds.get(f, "?")
        print("  %-28s %4d bytes (%s)" % (name, g.frame_of(f), src))
    print("  worst-case total from %s: %d bytes (target <= %d)" % (root, total, target))
    if g.unknown():
        print("  note: frames not found for", ", ".join(g.unknown()), "(counted as 0)")


if __name__ == "__main__":
    main()
