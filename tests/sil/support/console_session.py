"""Helpers of the scripted console sessions (tests/sil/test_console_serve.py,
test_console_identify.py, tests/pil/test_console_pil.py): the checks' record, the console run as a
user runs it, waiting for a drive state. Importing it puts tools/console on the path (dtc_drive)."""

import os
import signal
import subprocess
import sys
import time

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "tools", "console"))
CONSOLE = os.path.join(ROOT, "tools", "console", "dtc_console.py")

failures = []


def check(cond, what):
    """Records one check: prints ok/FAIL and the text; a failure is kept for the exit code."""
    print(("ok   " if cond else "FAIL ") + what, flush=True)
    if not cond:
        failures.append(what)


def console(port, *args, timeout_s=120):
    """dtc_console.py --port PORT ARGS...: (exit code, stdout, stderr)."""
    r = subprocess.run([sys.executable, CONSOLE, "--port", port] + list(args), capture_output=True, text=True,
                       timeout=timeout_s)
    return r.returncode, r.stdout, r.stderr


def serve(sil, scenario, link, pace, duration, sets=()):
    """`dtc-sil serve SCENARIO --serial LINK` at pace for duration s of simulated time, each of sets
    a --set override; returns the process once the link exists."""
    if os.path.exists(link):
        os.unlink(link)
    args = [sil, "serve", scenario, "--serial", link, "--pace", str(pace), "--duration-s", str(duration),
            "--set", "duration_s=%g" % duration, "-q"]
    for s in sets:
        args += ["--set", s]
    p = subprocess.Popen(args)
    for _ in range(300):
        if os.path.exists(link):
            return p
        time.sleep(0.02)
    p.kill()
    raise RuntimeError("dtc-sil serve made no link %s" % link)


def refused(fn, code, detail=None):
    """1 when fn() raises DriveError with error code (a name of dtc_drive.ERR) and, when given, the
    refusal detail (a name of dtc_drive.REFUSAL)."""
    from dtc_drive import DriveError, ERR, REFUSAL
    try:
        fn()
    except DriveError as e:
        return e.code == ERR[code] and (detail is None or e.detail == REFUSAL[detail])
    return False


def wait_state(d, state, limit_s=30.0):
    """Polls d.status() until the drive is in state; RuntimeError after limit_s."""
    end = time.monotonic() + limit_s
    s = None
    while time.monotonic() < end:
        s = d.status()
        if s["state"] == state:
            return s
        time.sleep(0.02)
    raise RuntimeError("the drive did not reach state %s (last: %s)" % (state, s))


def stop(p, sig=signal.SIGINT, wait_s=30):
    """Ends a served drive (dtc-sil serve, an emulator): sig, then a kill if it lingers."""
    p.send_signal(sig)
    try:
        p.wait(timeout=wait_s)
    except subprocess.TimeoutExpired:
        p.kill()


def exit_code():
    """The session's exit code: 1 when a check failed (their count printed), else 0."""
    if failures:
        print("%d check(s) failed" % len(failures))
        return 1
    return 0
