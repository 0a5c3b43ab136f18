#!/usr/bin/env python3
"""pil_compare.py - processor-in-the-loop comparison (docs/pil.md).

Replays one ISR recording (dtc-sil run --record-isr FILE) on the host build (pil-replay), on
simavr (pil-simavr + the cross-avr image) and on qemu-system-arm (the cross-cm0 image on
mps2-an385, semihosting), and compares every output record with the one recorded in SIL. Prints,
per target, "identical (N ISRs)" or the first differing ISR: index, field, both values.

  pil_compare.py RECORDING --targets host,simavr,qemu [--build-host DIR] [--build-avr DIR]
                 [--build-cm DIR] [--cycles]
  pil_compare.py --scenario TOML [--set KEY=VALUE ...] ...
                 records the scenario first (dtc-sil run --record-isr), then the same
  pil_compare.py ... --require calibrate,run,magnetise,speed,handover
                 fails unless the recording covers these phases (reported either way)
  pil_compare.py RECORDING --outputs FILE       compare an output file written elsewhere
  pil_compare.py RECORDING --corrupt-input K FIELD --targets host
                 negative check: the recording with input FIELD of ISR K changed must differ,
                 first at ISR K (exit 0 only if it does)

Exit status: 0 all identical (or the negative check caught the change where expected), 1 a
difference, 2 a usage, file or emulator error (a missing emulator is an error, never a skip).
"""
import argparse
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
FORMAT_H = os.path.join(ROOT, "hal", "replay", "pil_format.h")


def fields_of(macro):
    """(name, bytes) of an X-macro list in pil_format.h, in file order."""
    text = open(FORMAT_H).read()
    m = re.search(r"#define %s\(U16, U32\)(.*?)\n#define" % macro, text, re.S)
    if not m:
        raise SystemExit("pil_compare: %s not found in %s" % (macro, FORMAT_H))
    return [(n, 2 if w == "U16" else 4) for w, n in re.findall(r"\b(U16|U32)\((\w+)", m.group(1))]


OUT_FIELDS = fields_of("PIL_OUT_FIELDS")
IN_FIELDS = fields_of("PIL_IN_FIELDS")
OUT_BYTES = sum(w for _, w in OUT_FIELDS)
IN_BYTES = sum(w for _, w in IN_FIELDS)
HEADER_BYTES = 20
LAW_PM_DTC = 0  # DTC_LAW_PM_DTC (firmware/dtc/dtc_config_common.h)
LAW_PM_ITC = 6  # DTC_LAW_PM_ITC; every other law is an IM one
PM_LAWS = (LAW_PM_DTC, LAW_PM_ITC)


class Recording:
    def __init__(self, path):
        data = open(path, "rb").read()
        if len(data) < HEADER_BYTES or data[:4] != b"DPIL":
            raise SystemExit("pil_compare: %s: not an ISR recording" % path)
        (self.version, self.nconf, inb, outb, self.t1pr, _, self.count) = struct.unpack_from("<6HI", data, 4)
        if (inb, outb) != (IN_BYTES, OUT_BYTES):
            raise SystemExit("pil_compare: %s: record sizes %d/%d, pil_format.h says %d/%d"
                             % (path, inb, outb, IN_BYTES, OUT_BYTES))
        self.data = data
        self.body = HEADER_BYTES + 4 * self.nconf
        # the configuration starts with version and law (docs/pil.md)
        self.law = struct.unpack_from("<I", data, HEADER_BYTES + 4)[0] if self.nconf >= 2 else None
        rec = IN_BYTES + OUT_BYTES
        if len(data) != self.body + rec * self.count:
            raise SystemExit("pil_compare: %s: %d bytes, the header says %d ISRs" % (path, len(data), self.count))

    def outputs(self):
        rec = IN_BYTES + OUT_BYTES
        return b"".join(self.data[self.body + k * rec + IN_BYTES:self.body + (k + 1) * rec]
                        for k in range(self.count))


def decode(rec, off=0, fields=OUT_FIELDS):
    vals = {}
    for name, w in fields:
        vals[name] = struct.unpack_from("<H" if w == 2 else "<I", rec, off)[0]
        off += w
    return vals


def show(name, v, w):
    signed = v - (1 << (8 * w)) if v >= 1 << (8 * w - 1) else v
    return "%d (0x%0*x)" % (signed, 2 * w, v)


def first_difference(ref, got):
    """None if identical, else (isr, field, ref value, got value) or (isr, 'missing', ...)."""
    n = len(ref) // OUT_BYTES
    for k in range(n):
        a = ref[k * OUT_BYTES:(k + 1) * OUT_BYTES]
        b = got[k * OUT_BYTES:(k + 1) * OUT_BYTES]
        if len(b) < OUT_BYTES:
            return (k, "missing", "record", "none (output ends after %d ISRs)" % k)
        if a != b:
            da, db = decode(a), decode(b)
            for name, w in OUT_FIELDS:
                if da[name] != db[name]:
                    return (k, name, show(name, da[name], w), show(name, db[name], w))
    if len(got) > len(ref):
        return (n, "extra", "none", "%d more bytes" % (len(got) - len(ref)))
    return None


def run(cmd, cwd=None, timeout=600):
    try:
        p = subprocess.run(cmd, cwd=cwd, capture_output=True, timeout=timeout)
    except FileNotFoundError:
        raise SystemExit("pil_compare: %s not found (tools/setup.sh installs the emulators)" % cmd[0])
    if p.returncode != 0:
        sys.stderr.write(p.stdout.decode(errors="replace") + p.stderr.decode(errors="replace"))
        raise SystemExit("pil_compare: %s exited %d" % (" ".join(cmd), p.returncode))
    return p


def need(path, what):
    if not os.path.exists(path):
        raise SystemExit("pil_compare: %s missing (%s)" % (path, what))


def replay(target, rec_path, args, work):
    """Runs one target; returns (output bytes, wall seconds, cycle file, what the program printed)."""
    out = os.path.join(work, target + ".out")
    cyc = os.path.join(work, target + ".cycles")
    t0 = time.monotonic()
    said = ""
    if target == "host":
        exe = args.host_replay or os.path.join(args.build_host, "bin", "pil-replay")
        need(exe, "cmake --build --preset host")
        run([exe, rec_path, out])
    elif target == "simavr":
        exe = os.path.join(args.build_host, "bin", "pil-simavr")
        elf = args.avr_image or os.path.join(args.build_avr, "bin", "pil_avr.elf")
        need(exe, "cmake --build --preset host (needs libsimavr-dev)")
        need(elf, "cmake --build --preset cross-avr")
        said = "\n".join(l for l in run([exe, elf, rec_path, out, cyc]).stdout.decode(errors="replace").splitlines()
                          if l.startswith("ram:"))
    elif target == "qemu":
        qemu = shutil.which("qemu-system-arm")
        if qemu is None:
            raise SystemExit("pil_compare: qemu-system-arm not found (tools/setup.sh installs it)")
        elf = args.cm_image or os.path.join(args.build_cm, "bin", "pil_cm.elf")
        need(elf, "cmake --build --preset cross-cm0")
        d = os.path.join(work, "qemu")
        os.makedirs(d, exist_ok=True)
        shutil.copyfile(rec_path, os.path.join(d, "pil_in.bin"))
        run([qemu, "-M", "mps2-an385", "-nographic", "-monitor", "none", "-serial", "none",
             "-icount", "shift=%d" % QEMU_ICOUNT_SHIFT,
             "-semihosting-config", "enable=on,target=native", "-kernel", elf], cwd=d)
        shutil.move(os.path.join(d, "pil_out.bin"), out)
        shutil.move(os.path.join(d, "pil_cycles.bin"), cyc)
    else:
        raise SystemExit("pil_compare: unknown target %s" % target)
    wall = time.monotonic() - t0
    return open(out, "rb").read(), wall, cyc, said


# qemu -icount shift=N: every instruction advances the virtual clock by 2^N ns; SysTick counts the
# 25 MHz processor clock of mps2-an385, so one instruction is 2^N * 0.025 SysTick counts.
QEMU_ICOUNT_SHIFT = 6
QEMU_TICKS_PER_INSN = (1 << QEMU_ICOUNT_SHIFT) * 25e6 / 1e9


def cycle_stats(target, cyc, torque_at=None):
    """Per-ISR figures written by the emulator programs: u32 per ISR; with torque_at, also from
    that ISR on (the IM law's magnetisation ISRs are the cheaper ones)."""
    if not os.path.exists(cyc):
        return ""
    raw = open(cyc, "rb").read()
    vals = struct.unpack("<%dI" % (len(raw) // 4), raw)
    if not vals:
        return ""
    if target == "qemu":
        vals = [v / QEMU_TICKS_PER_INSN for v in vals]
        unit = "instructions (qemu -icount, Cortex-M0 code on the M3 model)"
    else:
        unit = "cycles (simavr, ATmega2560)"
    text = "app_isr %s: mean %.0f, worst %.0f over %d ISRs" % (unit, sum(vals) / len(vals), max(vals), len(vals))
    if torque_at and torque_at < len(vals):
        tail = vals[torque_at:]
        text += "; from ISR %d (torque allowed) on: mean %.0f, worst %.0f" % (torque_at, sum(tail) / len(tail), max(tail))
    return text


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("recording", nargs="?")
    ap.add_argument("--scenario", help="record this scenario first (dtc-sil run --record-isr)")
    ap.add_argument("--set", action="append", default=[], help="scenario override for --scenario")
    ap.add_argument("--require", default="", help="phases the recording must cover: calibrate,run,magnetise,speed,handover")
    ap.add_argument("--host-replay", help="host replay program (default BUILD_HOST/bin/pil-replay)")
    ap.add_argument("--avr-image", help="AVR image (default BUILD_AVR/bin/pil_avr.elf)")
    ap.add_argument("--cm-image", help="Cortex-M image (default BUILD_CM/bin/pil_cm.elf)")
    ap.add_argument("--max-seconds", type=float,
                    help="benchmark: print each target's replay wall clock against this budget (a figure, never a failure: it depends on the machine's load)")
    ap.add_argument("--expect-differ", default="",
                    help="targets that must differ from the recording (negative checks); the others must not")
    ap.add_argument("--expect-differ-at", nargs=2, metavar=("K", "FIELD"),
                    help="with --expect-differ: the first difference must be at ISR K in output FIELD")
    ap.add_argument("--targets", default="host,simavr,qemu")
    ap.add_argument("--outputs", help="compare this output file instead of running targets")
    ap.add_argument("--build-host", default=os.path.join(ROOT, "build", "host"))
    ap.add_argument("--build-avr", default=os.path.join(ROOT, "build", "cross-avr"))
    ap.add_argument("--build-cm", default=os.path.join(ROOT, "build", "cross-cm0"))
    ap.add_argument("--cycles", action="store_true", help="print per-ISR cycles / instructions")
    ap.add_argument("--corrupt-input", nargs=2, metavar=("K", "FIELD"),
                    help="negative check: add 1 to input FIELD of ISR K; the first difference must be at K")
    args = ap.parse_args()
    for a in ("host_replay", "avr_image", "cm_image", "build_host", "build_avr", "build_cm"):
        if getattr(args, a):
            setattr(args, a, os.path.abspath(getattr(args, a)))
    with tempfile.TemporaryDirectory(prefix="pil_rec_") as rec_dir:
        if args.scenario:
            args.recording = os.path.join(rec_dir, "scenario.rec")
            exe = os.path.join(args.build_host, "bin", "dtc-sil")
            need(exe, "cmake --build --preset host")
            cmd = [exe, "run", args.scenario, "--out", os.path.join(rec_dir, "run"), "--no-trace", "-q",
                   "--record-isr", args.recording]
            for kv in args.set:
                cmd += ["--set", kv]
            run(cmd)
            print("recorded %s %s" % (os.path.relpath(args.scenario, ROOT), " ".join("--set " + kv for kv in args.set)))
        elif not args.recording:
            ap.error("a RECORDING or --scenario is needed")
        return compare(args)


def coverage(rec, require):
    """Prints which phases the recording covers. Returns (False if a required one is missing,
    the IM law's first ISR with torque or None).

    calibrate  ISRs in CALIBRATE (gates off, offsets);
    run        the first ISR in RUN;
    magnetise  induction machine: the start-up magnetisation at zero torque (im_dtc.h) and its
               end, the first RUN ISR with a non-zero torque reference;
    speed      speed-loop updates once torque is allowed (from the first RUN ISR with a non-zero
               torque reference; the IM law measures speed during the magnetisation with its PI
               at rest, which does not count);
    handover   PM voltage model: the hand-over from the current model."""
    outs = rec.outputs()
    states, ticks, te_ref, cm, faults = [], [], [], [], set()
    for k in range(rec.count):
        d = decode(outs[k * OUT_BYTES:(k + 1) * OUT_BYTES])
        states.append(d["state"])
        ticks.append(d["speed_tick"])
        te_ref.append(d["te_ref_iq"])
        cm.append(d["on_cm"] if d["state"] == 2 else None)
        faults.add(d["fault"])
    cal = states.count(1)
    run_at = states.index(2) if 2 in states else None
    torque_at = next((k for k in range(rec.count) if states[k] == 2 and te_ref[k] != 0), None)
    speed = 0 if torque_at is None else sum(ticks[torque_at:])
    hand = next((k for k in range(1, rec.count) if cm[k - 1] == 1 and cm[k] == 0), None)
    magn = rec.law not in PM_LAWS and run_at is not None and torque_at is not None and torque_at > run_at
    have = {"calibrate": cal > 0, "run": run_at is not None, "magnetise": magn, "speed": speed > 0,
            "handover": hand is not None}
    law = "induction machine" if rec.law not in PM_LAWS else "PM"
    print("coverage (%s law): %d ISRs in CALIBRATE, RUN from ISR %s, torque from ISR %s%s, %d speed-loop "
          "updates with torque, hand-over to the voltage model at ISR %s, faults: %s"
          % (law, cal, run_at, torque_at,
             " (magnetisation %d ISRs)" % (torque_at - run_at) if magn else "",
             speed, hand, sorted(faults)))
    ok = True
    for r in [x for x in require.split(",") if x]:
        if r not in have:
            raise SystemExit("pil_compare: --require: unknown phase %s" % r)
        if not have[r]:
            print("coverage: the recording does not cover %s" % r)
            ok = False
    return ok, (torque_at if magn else None)


def compare(args):
    rec = Recording(args.recording)
    ref = rec.outputs()
    print("%s: %d ISRs, format version %d" % (args.recording, rec.count, rec.version))
    ok, torque_at = coverage(rec, args.require)
    if not ok:
        return 1
    if args.outputs:
        d = first_difference(ref, open(args.outputs, "rb").read())
        report("outputs", d, rec.count)
        return 0 if d is None else 1
    with tempfile.TemporaryDirectory(prefix="pil_") as work:
        rec_path = args.recording
        expect_at = None
        if args.corrupt_input:
            k, field = int(args.corrupt_input[0]), args.corrupt_input[1]
            names = [n for n, _ in IN_FIELDS]
            if field not in names or not 0 <= k < rec.count:
                raise SystemExit("pil_compare: --corrupt-input: ISR %d of %d, field one of %s"
                                 % (k, rec.count, ", ".join(names)))
            off = rec.body + k * (IN_BYTES + OUT_BYTES) + sum(w for n, w in IN_FIELDS[:names.index(field)])
            w = dict(IN_FIELDS)[field]
            data = bytearray(rec.data)
            fmt = "<H" if w == 2 else "<I"
            v = struct.unpack_from(fmt, data, off)[0]
            struct.pack_into(fmt, data, off, (v + 1) % (1 << (8 * w)))
            rec_path = os.path.join(work, "corrupt.rec")
            open(rec_path, "wb").write(data)
            expect_at = k
            print("negative check: input %s of ISR %d changed from %d to %d" % (field, k, v, (v + 1) % (1 << (8 * w))))
        status = 0
        for t in [x for x in args.targets.split(",") if x]:
            got, wall, cyc, said = replay(t, rec_path, args, work)
            d = first_difference(ref, got)
            report(t, d, rec.count, wall)
            if args.max_seconds is not None:
                # a figure, not a verdict: wall clock depends on what else the machine runs
                ok = wall <= args.max_seconds
                print("  %s: %d ISRs replayed in %.1f s wall clock (budget %.0f s)%s"
                      % (t, rec.count, wall, args.max_seconds, "" if ok else ": over the budget on this run"))
            if args.cycles:
                s = cycle_stats(t, cyc, torque_at)
                if s:
                    print("  %s" % s)
                if said:
                    print("  %s: %s" % (t, said))
            if t in args.expect_differ.split(","):
                if d is None:
                    print("  %s: expected to differ, but identical" % t)
                    status = 1
                elif args.expect_differ_at and (d[0], d[1]) != (int(args.expect_differ_at[0]), args.expect_differ_at[1]):
                    print("  %s: differs, but not first at ISR %s in field %s as expected"
                          % (t, args.expect_differ_at[0], args.expect_differ_at[1]))
                    status = 1
                else:
                    print("  %s: differs, as expected" % t)
            elif expect_at is None:
                status |= 0 if d is None else 1
            elif d is None or d[0] != expect_at:
                print("  %s: the change at ISR %d was NOT caught there" % (t, expect_at))
                status = 1
            else:
                print("  %s: caught at ISR %d, as expected" % (t, expect_at))
        return status


def report(target, d, n, wall=None):
    t = "" if wall is None else " [%.1f s]" % wall
    if d is None:
        print("%-7s identical (%d ISRs)%s" % (target + ":", n, t))
    else:
        print("%-7s first difference at ISR %d, field %s: recorded %s, %s %s%s"
              % (target + ":", d[0], d[1], d[2], target, d[3], t))


if __name__ == "__main__":
    sys.exit(main())
