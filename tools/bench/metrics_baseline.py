#!/usr/bin/python3
"""Behaviour-kept check: the metrics of every shipped scenario, compared between two builds.

    metrics_baseline.py record OUT.json [--dtc-sil PATH] [--jobs N] [--only NAME,...]
    metrics_baseline.py compare BASE.json NEW.json [--rel-tol X]
    metrics_baseline.py check BASE.json [--dtc-sil PATH] [--jobs N] [--rel-tol X]

`record` runs every scenario of tools/scenarios/*.toml and, on the induction machine's
im_dtc_speed.toml, every IM scheme (dtc, dsc, sfvc, dfoc, dsvm), each as `dtc-sil run` writes
it, and stores each run's metrics.json (and exit status) under the run's name. `compare` lists
every metric that differs between two records (numbers beyond --rel-tol, default 0: a pure
restructuring of the firmware keeps every figure to the last bit); it exits 1 when any differs or a
run is missing, 0 when all are equal. `check` records into a temporary file and compares.

A refactor that is meant to keep behaviour records main's figures first (`record base.json` with
main's build), then runs `check base.json` on its own build: any difference must be explained.
"""
import argparse
import concurrent.futures
import glob
import json
import math
import os
import subprocess
import sys
import tempfile

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
IM_SCHEMES = ["dtc", "dsc", "sfvc", "dfoc", "dsvm"]


def runs():
    """(name, scenario path, extra --set arguments) of every run the check covers."""
    out = []
    for path in sorted(glob.glob(os.path.join(ROOT, "tools", "scenarios", "*.toml"))):
        name = os.path.splitext(os.path.basename(path))[0]
        out.append((name, path, []))
        if name == "im_dtc_speed":
            for scheme in IM_SCHEMES:
                out.append((f"{name}[scheme={scheme}]", path, ["--set", f'control.scheme="{scheme}"']))
    return out


def run_one(dtc_sil, name, path, extra):
    with tempfile.TemporaryDirectory() as tmp:
        out_dir = os.path.join(tmp, "run")
        p = subprocess.run([dtc_sil, "run", path, "--out", out_dir, *extra],
                           capture_output=True, text=True)
        metrics = None
        mpath = os.path.join(out_dir, "metrics.json")
        if os.path.exists(mpath):
            with open(mpath) as f:
                metrics = json.load(f)
        return name, {"exit": p.returncode, "metrics": metrics,
                      "stderr": p.stderr.strip().splitlines()[-3:] if p.returncode else []}


def record(dtc_sil, jobs, only):
    todo = [r for r in runs() if not only or r[0] in only]
    result = {}
    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as ex:
        futs = [ex.submit(run_one, dtc_sil, *r) for r in todo]
        for i, fut in enumerate(concurrent.futures.as_completed(futs), 1):
            name, rec = fut.result()
            result[name] = rec
            print(f"[{i}/{len(todo)}] {name}: exit {rec['exit']}", file=sys.stderr, flush=True)
    return dict(sorted(result.items()))


def flatten(prefix, v, out):
    if isinstance(v, dict):
        for k, x in v.items():
            flatten(f"{prefix}.{k}" if prefix else k, x, out)
    elif isinstance(v, list):
        for i, x in enumerate(v):
            flatten(f"{prefix}[{i}]", x, out)
    else:
        out[prefix] = v
    return out


# Fields that describe the run, not the drive's behaviour.
VOLATILE = ("wall_time_s", "realtime_factor")


def differs(a, b, rel_tol):
    if isinstance(a, (int, float)) and isinstance(b, (int, float)) and not isinstance(a, bool):
        if math.isnan(a) and math.isnan(b):
            return False
        if rel_tol == 0:
            return a != b
        return abs(a - b) > rel_tol * max(abs(a), abs(b), 1e-12)
    return a != b


def compare(base, new, rel_tol):
    n_diff = 0
    for name in sorted(set(base) | set(new)):
        if name not in new or name not in base:
            print(f"{name}: only in {'base' if name in base else 'new'}")
            n_diff += 1
            continue
        b, n = base[name], new[name]
        if b["exit"] != n["exit"]:
            print(f"{name}: exit {b['exit']} -> {n['exit']} {n.get('stderr', '')}")
            n_diff += 1
        fb = flatten("", b["metrics"] or {}, {})
        fn = flatten("", n["metrics"] or {}, {})
        for key in sorted(set(fb) | set(fn)):
            if any(v in key for v in VOLATILE):
                continue
            if key not in fb or key not in fn:
                print(f"{name}: {key} only in {'base' if key in fb else 'new'}")
                n_diff += 1
            elif differs(fb[key], fn[key], rel_tol):
                print(f"{name}: {key} {fb[key]!r} -> {fn[key]!r}")
                n_diff += 1
    print(f"{len(base)} runs in base, {len(new)} in new: {n_diff} differences"
          + (f" (relative tolerance {rel_tol})" if rel_tol else " (exact)"))
    return 1 if n_diff else 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    default_bin = os.path.join(ROOT, "build", "host", "bin", "dtc-sil")
    for cmd in ("record", "check"):
        p = sub.add_parser(cmd)
        p.add_argument("file")
        p.add_argument("--dtc-sil", default=default_bin)
        p.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
        p.add_argument("--only", default="", help="comma-separated run names")
        if cmd == "check":
            p.add_argument("--rel-tol", type=float, default=0.0)
    p = sub.add_parser("compare")
    p.add_argument("base")
    p.add_argument("new")
    p.add_argument("--rel-tol", type=float, default=0.0)
    a = ap.parse_args()
    if a.cmd == "compare":
        with open(a.base) as f, open(a.new) as g:
            return compare(json.load(f), json.load(g), a.rel_tol)
    if not os.access(a.dtc_sil, os.X_OK):
        print(f"metrics_baseline: {a.dtc_sil} is not an executable (build the host preset)", file=sys.stderr)
        return 2
    only = set(x for x in a.only.split(",") if x)
    rec = record(a.dtc_sil, a.jobs, only)
    if a.cmd == "record":
        with open(a.file, "w") as f:
            json.dump(rec, f, indent=1, sort_keys=True)
        print(f"recorded {len(rec)} runs into {a.file}")
        return 0
    with open(a.file) as f:
        base = json.load(f)
    if only:
        base = {k: v for k, v in base.items() if k in only}
    return compare(base, rec, a.rel_tol)


if __name__ == "__main__":
    sys.exit(main())
