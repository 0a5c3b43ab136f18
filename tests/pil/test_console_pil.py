#!/usr/bin/python3
"""The console against the emulated target (docs/pil.md, docs/operate.md): one scripted console
session on an emulator's UART and the same session against the host build of the same image
(pil-console-host, its line a pseudo-terminal at the protocol's baud rate in simulated time). The
emulator is qemu-system-arm's mps2-an385 (its CMSDK UART0; the cross-cm0 console image
pil_cm_console.elf) or, with --simavr, simavr's ATmega2560 (its USART0 bridged to a
pseudo-terminal by pil-simavr --console; the cross-avr console image pil_avr_console.elf). Both
must give the same answers, and each answer must be the right one:

  hello            the protocol and firmware versions, the parameter table's hash, the bases;
  params           every row's description and value;
  status           powers up READY, disarmed, no fault, V_dc at the bench's DC link;
  arm refusal      refused with a speed reference set (ref_nonzero);
  params set/get   a torque limit set while disarmed reads back; out of range and read-only
                   writes are refused (range, read_only);
  save/restore     restore compiled gives the compiled-in value, restore the saved one;
  garbage          garbage, a bad CRC and a truncated frame before a request: it is answered, the
                   CRC errors are counted, nothing trips;
  capture          a capture at once: consecutive ticks, the DC link and the current as measured;
                   one deeper than the board's buffer refused by the console with the depth
                   HELLO reported;
  identify         on a bench without a machine the identification stops with open_phase, the
                   console exits 1 naming it, the drive is READY again;
  armed trip       armed on a bench without a machine the current-sensor check trips: the fault
                   and its snapshot (state run) in the log, the same on both; cleared, READY, the
                   fault log keeps it.

Ticks (the ISR count when a request arrives) and the line counters depend on when the host's
octets arrive and are left out of the comparison. So is HELLO's capture_buf_words32: the capture
buffer's depth is the board's (the AVR's is smaller, pil_console_avr.c); each target must report
its own and the console sizes the capture by it. Everything else is compared exactly.

On simavr the session must also run on the part itself: no octet may arrive while the
ATmega2560's receive buffer is full (pil-simavr's "would overrun" count), and its RAM line
(static data and stack peak) is printed.

Usage: test_console_pil.py PIL_CONSOLE_HOST PIL_CM_CONSOLE_ELF WORKDIR
       test_console_pil.py PIL_CONSOLE_HOST PIL_AVR_CONSOLE_ELF WORKDIR --simavr PIL_SIMAVR
"""

import csv
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time
import tty

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "sil", "support"))
import console_session  # noqa: E402
from console_session import exit_code, stop, wait_state  # noqa: E402
from dtc_drive import Drive, encode, CMD  # noqa: E402
# HELLO's capture depth (int32 words) of each console image: the F2812 board's on the host and the
# Cortex-M (capture.h), the AVR console image's (target/pil/CMakeLists.txt).
CAPTURE_WORDS32 = {"host": 512, "qemu": 512, "simavr": 128}
# qemu -icount shift=0: one instruction per ns of virtual time, so the 50 us SysTick period is
# 50,000 instructions of which the ISR takes about 8,000 (docs/pil.md) and the background loop
# gets the rest, whatever the host's speed.
QEMU_ICOUNT_SHIFT = 0


def check(target, cond, what):
    console_session.check(cond, "[%s] %s" % (target, what))


def console(port, *args):
    return console_session.console(port, "--timeout", "2", *args)


def timeless(s):
    """A status without what depends on when the request arrived."""
    return {k: v for k, v in s.items() if k not in ("tick", "rx_frames", "rx_crc_errors")}


def session(t, port, work):
    """The session; returns its answers (what both targets must give alike)."""
    A = {}
    with Drive(port, timeout_s=2.0) as d:
        h = d.hello()
        A["hello"] = {k: v for k, v in h.items() if k != "capture_buf_words32"}
        check(t, h["proto_version"] == 1 and h["isr_period_ns"] == 50000 and h["law"] == 0,
              "hello: protocol 1, 50 us, PM DTC (%s)" % h)
        check(t, h["capture_buf_words32"] == CAPTURE_WORDS32[t],
              "hello: the board's capture depth, %d int32 words" % h["capture_buf_words32"])
        s = wait_state(d, "ready")
        A["status_ready"] = timeless(s)
        check(t, not s["armed"] and s["fault"] == "none" and abs(s["vdc_v"] - h["v_base_v"]) < 0.05,
              "powers up READY, disarmed, no fault, V_dc %.3f V at the bench's %.1f V" % (s["vdc_v"], h["v_base_v"]))
        rows = d.params()
        A["params"] = [dict(r, value=d.param_get(r["name"])) for r in rows]
        check(t, len(rows) == h["param_count"] and any(r["name"] == "comm_timeout_s" for r in rows),
              "params: %d rows described, comm_timeout_s among them" % len(rows))
    tl_name = "speed.torque_limit_iq"
    # arm's conditions
    rc1, _, _ = console(port, "speed", "100")
    rc2, _, err = console(port, "arm")
    rc3, _, _ = console(port, "speed", "0")
    A["arm_refused"] = (rc1, rc2, "ref_nonzero" in err, rc3)
    check(t, A["arm_refused"] == (0, 1, True, 0), "arm refused with a speed reference set: %s" % err.strip())
    # parameters
    rc, out, _ = console(port, "params", "get", tl_name)
    tl0 = float(out)
    rc, out, err = console(port, "params", "set", tl_name, repr(0.75 * tl0))
    tl1 = float(out) if rc == 0 else None
    rc_get, out, _ = console(port, "params", "get", tl_name)
    A["param_set"] = (tl0, tl1, float(out))
    check(t, tl1 is not None and abs(tl1 - 0.75 * tl0) <= 1e-6 * tl0 and float(out) == tl1,
          "torque limit set while disarmed: %.6g -> %s, reads %s" % (tl0, tl1, out.strip()))
    rc_r, _, err_r = console(port, "params", "set", tl_name, "-1")
    rc_ro, _, err_ro = console(port, "params", "set", "board.v_base_mv", "1")
    A["param_refused"] = (rc_r, "range" in err_r, rc_ro, "read_only" in err_ro)
    check(t, A["param_refused"] == (1, True, 1, True), "out of range and read-only writes refused: %s / %s" %
          (err_r.strip(), err_ro.strip()))
    # save / restore
    rc_s, out_s, _ = console(port, "params", "save")
    rc_c, _, _ = console(port, "params", "restore", "compiled")
    _, v_c, _ = console(port, "params", "get", tl_name)
    rc_st, _, _ = console(port, "params", "restore")
    _, v_s, _ = console(port, "params", "get", tl_name)
    A["save_restore"] = (rc_s, out_s.strip(), rc_c, float(v_c), rc_st, float(v_s))
    check(t, rc_s == 0 and rc_c == 0 and rc_st == 0 and float(v_c) == tl0 and float(v_s) == tl1,
          "save, restore compiled (%s), restore stored (%s)" % (v_c.strip(), v_s.strip()))
    # garbage, a bad CRC, a truncated frame, then a request
    with Drive(port, timeout_s=2.0) as d:
        before = d.status()["rx_crc_errors"]
        bad = bytearray(encode(CMD["STATUS"], 7))
        bad[-1] ^= 0x40
        junk = bytes((k * 37 + 11) & 0xFF for k in range(200)) + bytes(bad) + encode(CMD["HELLO"], 9)[:5]
        d.ser.write(junk)
        d.ser.flush()
        s = d.status()
        A["garbage"] = (s["rx_crc_errors"] - before, timeless(s))
        check(t, s["rx_crc_errors"] > before and s["state"] == "ready" and s["fault"] == "none",
              "garbage answered after: %d CRC errors counted, no trip" % (s["rx_crc_errors"] - before))
    # capture at once
    cap = os.path.join(work, "capture")
    rc, _, err = console(port, "capture", "--channels", "vdc_v,i_a_a,sector", "--samples", "32", "--trigger", "now",
                         "--out", cap)
    with open(os.path.join(cap, "capture.csv"), encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    ticks = [int(r["tick"]) for r in rows]
    vals = [(float(r["vdc_v"]), float(r["i_a_a"]), float(r["sector"])) for r in rows]
    A["capture"] = vals
    check(t, rc == 0 and len(rows) == 32 and all(b - a == 1 for a, b in zip(ticks, ticks[1:])) and
          all(abs(v[0] - A["status_ready"]["vdc_v"]) < 1e-9 and v[1] == 0.0 for v in vals),
          "capture now: 32 consecutive ticks, V_dc and i_a as measured (%s)" % err.strip())
    # a capture deeper than the board's buffer: the console refuses it naming the depth it read
    depth = CAPTURE_WORDS32[t]
    rc, _, err = console(port, "capture", "--channels", "vdc_v,i_a_a,sector", "--samples", str(depth // 3 + 1),
                         "--trigger", "now", "--out", cap + "_deep")
    check(t, rc == 1 and ("holds %d" % depth) in err and ("at most %d samples" % (depth // 3)) in err,
          "capture deeper than the buffer refused with its depth: %s" % err.strip())
    # the identification on a bench without a machine
    rc, _, err = console(port, "identify", "--timeout", "60")
    with Drive(port, timeout_s=2.0) as d:
        s = d.status()
    A["identify"] = (rc, err.strip(), timeless(s))
    check(t, rc == 1 and "open_phase" in err and s["state"] == "ready",
          "identify without a machine stops with open_phase, READY again: %s" % err.strip())
    # armed on a bench without a machine: no current follows the voltage, the current-sensor check
    # trips (within 20 periods, before the shortest command timeout could: comm_timeout is
    # checked in SIL, sil.console_serve); the fault and its snapshot, the same on both
    rc1, _, err = console(port, "arm")
    with Drive(port, timeout_s=2.0) as d:
        st = wait_state(d, "fault")
    rc3, out, _ = console(port, "faults", "--json")
    faults = json.loads(out) if rc3 == 0 else []
    A["armed_trip"] = ((rc1, rc3), [{k: v for k, v in f.items() if k != "tick"} for f in faults], timeless(st))
    check(t, rc1 == 0 and faults and faults[0]["reason"] == "current_sensor" and
          faults[0]["snapshot"]["state"] == "run" and st["fault"] == "current_sensor" and not st["armed"],
          "armed without a machine: fault current_sensor, disarmed, in the log with its snapshot (%s)" %
          (faults[0]["reason"] if faults else "none"))
    rc5, _, _ = console(port, "clear")
    with Drive(port, timeout_s=2.0) as d:
        s = wait_state(d, "ready")
        kept = d.faults()
    A["clear"] = (rc5, timeless(s), len(kept), kept[0]["reason"] if kept else None)
    check(t, rc5 == 0 and s["fault"] == "none" and kept and kept[0]["reason"] == "current_sensor",
          "cleared: READY, the fault log keeps it")
    return A


def run_host(binary, work):
    link = os.path.join(work, "link")
    p = subprocess.Popen([binary, link])
    for _ in range(300):
        if os.path.exists(link):
            break
        time.sleep(0.02)
    return p, link


def run_qemu(elf, work):
    qemu = shutil.which("qemu-system-arm")
    if qemu is None:
        raise SystemExit("test_console_pil: qemu-system-arm not found (tools/setup.sh installs it)")
    log = open(os.path.join(work, "qemu.log"), "w+", encoding="utf-8")
    p = subprocess.Popen([qemu, "-M", "mps2-an385", "-nographic", "-monitor", "none", "-serial", "pty",
                          "-icount", "shift=%d" % QEMU_ICOUNT_SHIFT, "-kernel", elf],
                         stdout=log, stderr=subprocess.STDOUT, cwd=work)
    pts = None
    for _ in range(300):
        log.seek(0)
        m = re.search(r"char device redirected to (/dev/pts/\d+)", log.read())
        if m:
            pts = m.group(1)
            break
        time.sleep(0.02)
    if pts is None:
        p.kill()
        raise SystemExit("test_console_pil: qemu made no pseudo-terminal (%s)" % log.name)
    return p, pts


def run_simavr(simavr, elf, work):
    link = os.path.join(work, "link")
    log = open(os.path.join(work, "simavr.log"), "w+", encoding="utf-8")
    # the ATmega2560 with 32 KB of external SRAM (target/pil/pil_console_avr.c)
    p = subprocess.Popen([simavr, "--console", elf, link, "--ram-end", "7fff"], stdout=log, stderr=subprocess.STDOUT,
                         cwd=work)
    for _ in range(300):
        if os.path.exists(link):
            break
        time.sleep(0.02)
    return p, link


def simavr_report(work):
    """pil-simavr's lines at exit (RAM, ISR cycles, line counts), printed; the would-overrun count."""
    with open(os.path.join(work, "simavr.log"), encoding="utf-8") as f:
        text = f.read()
    for line in text.splitlines():
        if line.startswith(("ram:", "isr:", "line:", "simulated:")):
            print("[simavr] " + line, flush=True)
    m = re.search(r"(\d+) would overrun", text)
    return int(m.group(1)) if m else None


def diff(a, b, path=""):
    """The first places where a and b differ."""
    if type(a) is not type(b):
        return ["%s: %r != %r" % (path, a, b)]
    if isinstance(a, dict):
        out = []
        for k in sorted(set(a) | set(b)):
            out += diff(a.get(k), b.get(k), "%s.%s" % (path, k))
        return out
    if isinstance(a, (list, tuple)):
        if len(a) != len(b):
            return ["%s: %d != %d items" % (path, len(a), len(b))]
        out = []
        for k, (x, y) in enumerate(zip(a, b)):
            out += diff(x, y, "%s[%d]" % (path, k))
        return out
    return [] if a == b else ["%s: %r != %r" % (path, a, b)]


def main():
    host_bin, elf, work = sys.argv[1:4]
    simavr = sys.argv[5] if len(sys.argv) == 6 and sys.argv[4] == "--simavr" else None
    emulator = "simavr" if simavr else "qemu"
    shutil.rmtree(work, ignore_errors=True)
    answers = {}
    for target in ("host", emulator):
        w = os.path.join(work, target)
        os.makedirs(w)
        if target == "host":
            p, port = run_host(host_bin, w)
        elif target == "simavr":
            p, port = run_simavr(simavr, elf, w)
        else:
            p, port = run_qemu(elf, w)
        # held open for the whole session, raw: qemu's pseudo-terminal stays connected between the
        # console's invocations (a closed one drops what the guest sends until it reconnects)
        keep = os.open(port, os.O_RDWR | os.O_NOCTTY)
        tty.setraw(keep)
        try:
            t0 = time.monotonic()
            answers[target] = session(target, port, w)
            print("[%s] session took %.1f s" % (target, time.monotonic() - t0), flush=True)
        finally:
            os.close(keep)
            stop(p, signal.SIGTERM)
        with open(os.path.join(w, "answers.json"), "w", encoding="utf-8") as f:
            json.dump(answers[target], f, indent=1)
        if target == "simavr":
            overruns = simavr_report(w)
            check(target, overruns == 0, "no octet arrived while the part's receive buffer was full (%s)" % overruns)
    d = diff(answers["host"], answers[emulator])
    check("host = %s" % emulator, not d, "the same answers from %s's UART as from the host build (%d steps)%s" %
          (emulator, len(answers["host"]), "" if not d else ": " + "; ".join(d[:8])))
    return exit_code()


if __name__ == "__main__":
    sys.exit(main())
