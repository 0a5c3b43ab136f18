#!/usr/bin/python3
"""A scripted console session against `dtc-sil serve` from standstill (docs/operate.md), the SIL
targets of the serial protocol:

 1. the drive comes up disarmed (READY, gates off); arm, speed 1000 rpm: the status speed within
    2 % once settled;
 2. a capture of the estimated torque and flux components equals the trace's torque_est_nm,
    psi_alpha_est_wb, psi_beta_est_wb at the same ISRs within one LSB of the captured format
    (IQ24 of the torque and flux bases);
 3. a parameter set while disarmed changes the behaviour it should; one refused while armed is
    refused (PROTO_ERR_ARMED) and changes nothing;
 4. the command timeout (comm_timeout_s) disarms within its setting plus one speed-loop period;
 5. the telemetry stream; the scenario's [faults] event (the encoder signal lost at faults.time_s) shows in `faults`
    with its reason and a snapshot at speed.

Usage: test_console_serve.py DTC_SIL SCENARIO WORKDIR
"""

import csv
import json
import math
import os
import shutil
import signal
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "support"))
from console_session import check, console, failures, wait_state  # noqa: E402
from dtc_drive import Drive, DriveError, ERR  # noqa: E402

FRACTION = 0.75    # the torque limit set while disarmed, of its value
FAULT_T_S = 25.0   # the scenario's fault (faults.time_s): after the session's other steps
DURATION_S = 26.0
PACE = 1.0

SAVED = [0.0, 0.0]  # the torque limit saved, the compiled-in one


def wait_tick(d, tick, limit_s=60.0):
    end = time.monotonic() + limit_s
    while time.monotonic() < end:
        s = d.status()
        if s["tick"] >= tick:
            return s
        time.sleep(0.02)
    raise RuntimeError("the simulation did not reach tick %d" % tick)


def main():
    sil, scenario, work = sys.argv[1], sys.argv[2], sys.argv[3]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    link = os.path.join(work, "link")
    out = os.path.join(work, "out")
    srv = subprocess.Popen([sil, "serve", scenario, "--serial", link, "--pace", str(PACE), "--duration-s",
                            str(DURATION_S), "--out", out, "--set", "faults.time_s=%g" % FAULT_T_S,
                            "--set", "faults.encoder_lost=true", "--set", "duration_s=%g" % DURATION_S, "-q"])
    try:
        for _ in range(200):
            if os.path.exists(link):
                break
            time.sleep(0.02)
        session(link, work)
    finally:
        try:
            srv.wait(timeout=120)
        except subprocess.TimeoutExpired:
            srv.send_signal(signal.SIGINT)
            srv.wait(timeout=30)
    check(srv.returncode == 0, "dtc-sil serve exits 0 (%s)" % srv.returncode)
    # a restart on the same link boots into the saved parameters (stopped by SIGINT below: its 60 s
    # of simulated time at real-time pace only bound a session that hangs; 8 s ran out on a loaded
    # machine before the session's console processes had finished)
    srv = subprocess.Popen([sil, "serve", scenario, "--serial", link, "--pace", "1", "--duration-s", "60", "-q"])
    try:
        for _ in range(200):
            if os.path.exists(link):
                break
            time.sleep(0.02)
        with Drive(link, timeout_s=2.0) as d:
            v = d.param_get("speed.torque_limit_iq")
            check(abs(v - SAVED[0]) <= d.bases()["t"] / 2 ** 24,
                  "after a restart the saved torque limit %.4f N*m is in force (%.4f)" % (SAVED[0], v))
        rc, _, err = console(link, "params", "restore", "compiled")
        check(rc == 0, "params restore compiled accepted: %s" % err.strip())
        with Drive(link, timeout_s=2.0) as d:
            v = d.param_get("speed.torque_limit_iq")
            check(abs(v - SAVED[1]) <= d.bases()["t"] / 2 ** 24,
                  "restore of the compiled-in set: %.4f N*m again (%.4f)" % (SAVED[1], v))
        rc, _, err = console(link, "params", "restore")
        check(rc == 0, "params restore (the stored copy) accepted: %s" % err.strip())
        with Drive(link, timeout_s=2.0) as d:
            v = d.param_get("speed.torque_limit_iq")
            check(abs(v - SAVED[0]) <= d.bases()["t"] / 2 ** 24,
                  "params restore loads the stored torque limit %.4f N*m again (%.4f)" % (SAVED[0], v))
        rc, _, err = console(link, "params", "restore", "elsewhere")
        check(rc == 2, "params restore with an unknown source is a usage error (%d)" % rc)
    finally:
        srv.send_signal(signal.SIGINT)
        srv.wait(timeout=30)
    compare_capture(work, out)
    if failures:
        print("%d check(s) failed" % len(failures))
        return 1
    return 0


def session(link, work):
    global CAP, TS_S, LSB
    with Drive(link, timeout_s=2.0) as d:
        h = d.hello()
        ts = h["isr_period_ns"] * 1e-9
        TS_S = ts
        b = d.bases()
        LSB = {"torque_est_nm": b["t"] / 2 ** 24, "psi_alpha_est_wb": b["psi"] / 2 ** 24,
               "psi_beta_est_wb": b["psi"] / 2 ** 24}
        s = wait_state(d, "ready")
        check(not s["armed"] and s["fault"] == "none", "powers up disarmed, no fault: %s" % s["state"])
        # --- 1. arm, 1000 rpm from standstill -------------------------------------------------
        rc, _, err = console(link, "speed", "100")
        check(rc == 0, "speed 100 accepted while disarmed")
        rc, _, err = console(link, "arm")
        check(rc == 1 and "ref_nonzero" in err, "arm refused with a reference not zero: %s" % err.strip())
        rc, _, _ = console(link, "speed", "0")
        rc, _, err = console(link, "arm")
        check(rc == 0, "arm accepted at zero references (%s)" % err.strip())
        t0 = d.status()["tick"]
        d.speed(1000.0)
        wait_tick(d, t0 + int(1.5 / ts))
        speeds = []
        for _ in range(5):
            speeds.append(d.status()["speed_rpm"])
            time.sleep(0.05)
        rc, txt, _ = console(link, "status", "--json")
        js = json.loads(txt)
        check(rc == 0 and js["state"] == "run" and js["armed"] and
              all(k in js for k in ("state", "fault", "speed_rpm", "torque_est_nm")),
              "status --json: state run, fields state fault speed_rpm torque_est_nm")
        mean = sum(speeds) / len(speeds)
        check(abs(mean - 1000.0) <= 20.0, "status speed %.1f rpm within 2 %% of 1000 rpm" % mean)
        garbage_checks(d)
        # telemetry: a stream at 10 ms (200 periods), every frame one decimation apart
        dec, tm = d.telemetry(["speed_rpm", "torque_est_nm"], 200, 20)
        steps = sorted(set(b[0] - a[0] for a, b in zip(tm, tm[1:])))
        check(dec == 200 and len(tm) == 20 and steps == [200] and
              all(abs(v["speed_rpm"] - 1000.0) <= 20.0 for _, v in tm),
              "telemetry: 20 frames 200 periods apart at 1000 rpm (decim %d, steps %s)" % (dec, steps))
        # --- 2. capture -------------------------------------------------------------------------
        cap = os.path.join(work, "cap")
        rc, txt, err = console(link, "capture", "--channels", "torque_est_nm,psi_alpha_est_wb,psi_beta_est_wb",
                               "--samples", "100", "--trigger", "rising:psi_alpha_est_wb:0", "--pre", "20",
                               "--out", cap)
        check(rc == 0 and os.path.exists(os.path.join(cap, "capture.csv")) and
              os.path.exists(os.path.join(cap, "capture.png")), "capture wrote capture.csv and capture.png (%s)"
              % err.strip())
        CAP = os.path.join(cap, "capture.csv")
        # --- 3. a parameter: set while disarmed acts, refused while armed -----------------------
        param_checks(d, link, ts)
        # --- 4. the command timeout -------------------------------------------------------------
        d.param_set("comm_timeout_s", 0.2)
        check(abs(d.param_get("comm_timeout_s") - 0.2) < 1e-9, "comm_timeout_s reads back 0.2 s")
        d.speed(0.0)
        s = wait_state(d, "run") if d.status()["state"] != "run" else d.status()
        last = d.status()["tick"]      # the last valid frame before the silence
        time.sleep(1.0 / PACE)          # 1 s simulated without a frame
        s = d.status()
        check(s["state"] == "fault" and s["fault"] == "comm_timeout" and not s["armed"],
              "silence while armed: fault comm_timeout, disarmed (%s, %s)" % (s["state"], s["fault"]))
        f = d.faults()[0]
        speed_div = speed_loop_periods(d)
        late = f["tick"] - last
        check(f["reason"] == "comm_timeout" and late <= math.ceil(0.2 / ts) + speed_div,
              "the timeout tripped %d periods after the last frame (setting %d + one speed-loop period %d)"
              % (late, math.ceil(0.2 / ts), speed_div))
        d.param_set("comm_timeout_s", 0.0)
        # --- 5. the scenario's fault ------------------------------------------------------------
        d.clear()
        wait_state(d, "ready")
        d.arm()
        d.speed(1000.0)
        now = d.status()["tick"]
        check(now < int((FAULT_T_S - 1.5) / ts), "the session reached the scenario's fault with 1.5 s to spare "
              "(tick %d; a slower machine needs a later faults.time_s)" % now)
        s = wait_tick(d, int((FAULT_T_S - 0.05) / ts))
        check(abs(s["speed_rpm"] - 1000.0) <= 20.0, "at 1000 rpm again before the fault (%.1f rpm)" % s["speed_rpm"])
        wait_tick(d, int((FAULT_T_S + 0.2) / ts))
        rc, txt, err = console(link, "faults", "--json")
        fl = json.loads(txt) if rc == 0 else []
        e = fl[0] if fl else {}
        check(rc == 0 and e.get("reason") == "encoder" and e.get("tick", 0) >= int(FAULT_T_S / ts) and
              all(k in e for k in ("reason", "detail", "tick", "snapshot")),
              "faults --json: the scenario's encoder loss, newest, with reason, detail, tick, snapshot: %s"
              % {k: e.get(k) for k in ("reason", "detail", "tick")})
        sn = e.get("snapshot", {})
        check(sn.get("state") == "run" and sn.get("speed_rpm", 0.0) > 100.0 and abs(sn.get("vdc_v", 0.0) - 70.0) < 3.5,
              "its snapshot: in run, the rotor turning (the measured speed decays while the count stands "
              "still: %.0f rpm), V_dc %.1f V" % (sn.get("speed_rpm", 0.0), sn.get("vdc_v", 0.0)))
        check(len(fl) >= 2 and fl[1]["reason"] == "comm_timeout", "the log kept the timeout across the clear")


def garbage_checks(d):
    """Garbage, truncated frames, bad CRCs, unknown ids and out-of-range values at full line load:
    error frames where a frame was decoded, no answer otherwise, and the drive runs on."""
    import random
    from dtc_drive import encode, CMD
    rng = random.Random(7)
    junk = bytearray()
    for k in range(200):
        kind = k % 4
        if kind == 0:
            junk += bytes(rng.randrange(256) for _ in range(rng.randrange(1, 40)))
        elif kind == 1:
            f = encode(CMD["STATUS"], 200, b"")
            junk += f[:rng.randrange(1, len(f))]
        else:
            f = bytearray(encode(CMD["SPEED_REF"], 201, b"\x00\x00\x00\x00"))
            f[rng.randrange(1, len(f))] ^= 1 << rng.randrange(8)
            junk += f
    t0 = d.status()["tick"]
    d.ser.write(bytes(junk))  # about 4 kB: 0.35 s of line time at 115200 baud
    d.ser.flush()
    time.sleep(0.5)
    d.ser.reset_input_buffer()
    d.dec.buf.clear()
    for cmd, payload, code in ((0x55, b"", "UNKNOWN_CMD"), (CMD["SPEED_REF"], b"\x01", "LENGTH"),
                               (CMD["PARAM_READ"], b"\xfe\xff", "PARAM_ID"),
                               (CMD["CAPTURE_SETUP"], bytes(24), "RANGE"),
                               (CMD["FAULTLOG_READ"], b"\x07\x00", "RANGE")):
        try:
            d.request(cmd, payload)
            got = None
        except DriveError as e:
            got = e.code
        check(got == ERR[code], "request 0x%02x answered with error %s (%s)" % (cmd, code, got))
    s = d.status()
    check(s["state"] == "run" and s["fault"] == "none" and s["tick"] > t0,
          "after garbage at full line load the drive still runs (%s, %s)" % (s["state"], s["fault"]))
    check(abs(s["speed_ref_rpm"] - 1000.0) < 0.5, "no corrupted frame changed the reference (%.1f rpm)"
          % s["speed_ref_rpm"])


def speed_loop_periods(d):
    return int(round(d.param_get("speed.speed_div"))) if any(r["name"] == "speed.speed_div" for r in d.params()) else 1


def param_checks(d, link, ts):
    """While armed, a parameter that is not live is refused (armed) and keeps its value. While
    disarmed, the speed loop's torque limit set to FRACTION of its value (above the configuration's
    own torque reference, which the law's check keeps within the limit): re-armed, the speed PI's
    torque reference saturates at the new limit, not the old one. The old limit is restored."""
    rows = {r["name"]: r for r in d.params()}
    check("comm_timeout_s" in rows, "params list has comm_timeout_s")
    rc, txt, _ = console(link, "params", "list")
    check(rc == 0 and "comm_timeout_s" in txt, "params list prints the table")
    lim = "speed.torque_limit_iq"
    check(lim in rows, "%s is in the table" % lim)
    old = d.param_get(lim)
    # a row that is not live: refused while armed, unchanged
    fixed = [n for n, r in rows.items() if r["flags"] & 2 and not r["flags"] & 1]
    check(bool(fixed), "the table has rows that may be written only while disarmed")
    name = lim if lim in fixed else fixed[0]
    before = d.param_get(name)
    rc, _, err = console(link, "params", "set", name, repr(before))
    check(rc == 1 and "armed" in err, "params set %s while armed refused: %s" % (name, err.strip()))
    check(d.param_get(name) == before, "%s unchanged by the refused write" % name)
    d.disarm()
    d.speed(0.0)
    wait_state(d, "ready")
    rc, txt, err = console(link, "params", "set", lim, repr(FRACTION * old))
    new = d.param_get(lim)
    SAVED[:] = [new, old]
    check(rc == 0 and abs(new - FRACTION * old) <= d.bases()["t"] / 2 ** 24,
          "params set %s %.4f N*m while disarmed (reads %.4f)" % (lim, FRACTION * old, new))
    wait_state(d, "ready")
    rc, txt, err = console(link, "params", "save")
    check(rc == 0 and "saved" in txt, "params save while disarmed: %s%s" % (txt.strip(), err.strip()))
    d.arm()
    try:
        d.save()
        got = None
    except DriveError as e:
        got = e.code
    check(got == ERR["ARMED"], "params save while armed refused (%s)" % got)
    d.speed(1000.0)
    ticks, cols = d.capture(["torque_ref_nm", "speed_rpm"], 200, "now", 0, 20)
    tmax = max(abs(v) for v in cols["torque_ref_nm"])
    lsb = d.bases()["t"] / 2 ** 24
    check(abs(tmax - new) <= lsb and new < old - lsb,
          "re-armed, the torque reference saturates at the new limit %.4f N*m (max %.4f; old %.4f)"
          % (new, tmax, old))
    d.disarm()
    d.speed(0.0)
    wait_state(d, "ready")
    d.param_set(lim, old)
    wait_state(d, "ready")
    d.arm()
    d.speed(1000.0)


def compare_capture(work, out):
    """capture.csv against trace.csv at the same ISRs (tick = round(t_s / ts)) within one LSB of
    the captured format (IQ24). The capture's SI values are its raw integers times the console's
    scale (the bases HELLO reports, in the configuration's milli-units); the trace's are the same
    raw integers times the SIL's exact bases. So each channel's raw values are recovered from the
    capture exactly, the one scale between the two fitted (least squares), and every sample must
    then agree within one LSB; the fitted scale must equal the console's within the milli-unit
    bases' precision (1e-5)."""
    try:
        with open(CAP, encoding="utf-8") as f:
            cap = list(csv.DictReader(f))
    except (NameError, OSError) as e:
        check(False, "capture.csv readable (%s)" % e)
        return
    want = {int(r["tick"]): r for r in cap}
    pairs = {c: [] for c in LSB}
    with open(os.path.join(out, "trace.csv"), encoding="utf-8") as f:
        for row in csv.DictReader(f):
            k = int(round(float(row["t_s"]) / TS_S))
            if k in want:
                for c in LSB:
                    pairs[c].append((int(round(float(want[k][c]) / LSB[c])), float(row[c])))
    check(len(pairs["torque_est_nm"]) == len(cap), "every captured tick is a trace row (%d of %d)"
          % (len(pairs["torque_est_nm"]), len(cap)))
    for c, pr in pairs.items():
        den = sum(r * r for r, _ in pr)
        if den == 0:
            check(False, "capture %s is not all zero" % c)
            continue
        scale = sum(r * t for r, t in pr) / den
        worst = max(abs(t / scale - r) for r, t in pr)
        check(worst <= 1.0 and abs(scale / LSB[c] - 1.0) < 1e-5,
              "capture %s equals the trace within one LSB (worst %.3f LSB; trace scale / console scale - 1 = %.1e)"
              % (c, worst, scale / LSB[c] - 1.0))


if __name__ == "__main__":
    sys.exit(main())
