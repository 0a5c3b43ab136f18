#!/usr/bin/python3
"""dtc_console - operate the DTC drive over its serial line (docs/operate.md).

    dtc_console.py --port PATH status [--json]
    dtc_console.py --port PATH arm | disarm | clear
    dtc_console.py --port PATH speed RPM | torque NM
    dtc_console.py --port PATH faults [--json]
    dtc_console.py --port PATH params list | get NAME | set NAME VALUE | save | restore [stored|compiled]
                                      | export FILE
    dtc_console.py --port PATH capture --channels A,B.. --samples N --trigger SPEC --pre N --out DIR
    dtc_console.py --port PATH identify [--json] [--out DIR] [--apply [--save]]
    dtc_console.py --port PATH watch

PATH is a serial port, the link of `dtc-sil serve --serial PATH`, or an emulator's UART. Values
are SI. Every subcommand exits 1 with a message naming what went wrong when the drive refuses or
does not answer (2 for a bad command line).
"""

import argparse
import csv
import json
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from dtc_drive import Drive, DriveError  # noqa: E402


def _print_status(s, as_json):
    if as_json:
        print(json.dumps(s, indent=2))
        return
    print("state %s%s, fault %s%s" % (s["state"], " (armed)" if s["armed"] else "", s["fault"],
                                      "" if s["fault"] == "none" else " detail %d" % s["fault_detail"]))
    print("speed %.1f rpm (ref %.1f, %s mode), torque %.4f N*m (ref %.4f), flux %.4f Wb, V_dc %.2f V" %
          (s["speed_rpm"], s["speed_ref_rpm"], s["mode"], s["torque_est_nm"], s["torque_ref_nm"], s["flux_est_wb"],
           s["vdc_v"]))


def cmd_status(d, a):
    _print_status(d.status(), a.json)


def cmd_faults(d, a):
    f = d.faults()
    if a.json:
        print(json.dumps(f, indent=2))
        return
    if not f:
        print("no faults since boot")
    for e in f:
        s = e["snapshot"]
        print("tick %d: %s (detail %d) in %s; i_abc %.3f %.3f %.3f A, V_dc %.2f V, %.1f rpm, T_est %.4f N*m" %
              (e["tick"], e["reason"], e["detail"], s["state"], s["i_a_a"], s["i_b_a"], s["i_c_a"], s["vdc_v"],
               s["speed_rpm"], s["torque_est_nm"]))


def cmd_params(d, a):
    if a.op == "list":
        for r in d.params():
            flags = ("ro " if r["flags"] & 1 else "") + ("disarmed-only" if r["flags"] & 2 else "")
            print("%5d  %-32s %14.6g %-8s %s" % (r["id"], r["name"], d.param_get(r["name"]), r["unit"], flags))
    elif a.op == "get":
        need(a.args, 1, "params get NAME")
        print("%.9g" % d.param_get(a.args[0]))
    elif a.op == "set":
        need(a.args, 2, "params set NAME VALUE")
        print("%.9g" % d.param_set(a.args[0], a.args[1]))
    elif a.op == "save":
        print("saved, copy %d" % d.save())
    elif a.op == "restore":
        if len(a.args) > 1 or (a.args and a.args[0] not in RESTORE_SOURCE):
            raise SystemExit2("usage: dtc_console.py --port PATH params restore [stored|compiled]")
        src = a.args[0] if a.args else "stored"
        d.restore(RESTORE_SOURCE[src])
        print("restored the %s parameters" % src)
    elif a.op == "export":
        need(a.args, 1, "params export FILE")
        text, left = d.firmware_toml()
        with open(a.args[0], "w", encoding="utf-8") as f:
            f.write("# read from the drive on %s; parameters without a [firmware] key: %s\n"
                    % (a.port, ", ".join(left) if left else "none"))
            f.write(text)
        print("wrote %s" % a.args[0])


# params restore's sources (proto.h PARAMS_RESTORE): the newest valid stored copy, the compiled-in set.
RESTORE_SOURCE = {"stored": 0, "compiled": 1}


def need(args, n, usage):
    if len(args) != n:
        raise SystemExit2("usage: dtc_console.py --port PATH %s" % usage)


class SystemExit2(Exception):
    pass


def cmd_capture(d, a):
    chans = [c.strip() for c in a.channels.split(",") if c.strip()]
    ticks, cols = d.capture(chans, a.samples, a.trigger, a.pre, a.decim, a.timeout)
    os.makedirs(a.out, exist_ok=True)
    path = os.path.join(a.out, "capture.csv")
    with open(path, "w", newline="", encoding="utf-8") as f:
        w = csv.writer(f)
        w.writerow(["tick"] + chans)
        for k, t in enumerate(ticks):
            w.writerow([t] + [repr(cols[c][k]) for c in chans])
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, axs = plt.subplots(len(chans), 1, sharex=True, figsize=(8, 2 + 1.6 * len(chans)), squeeze=False)
        for ax, c in zip(axs[:, 0], chans):
            ax.plot(ticks, cols[c], lw=0.8)
            ax.set_ylabel(c)
            ax.grid(True, alpha=0.3)
        axs[-1, 0].set_xlabel("ISR tick")
        fig.tight_layout()
        fig.savefig(os.path.join(a.out, "capture.png"), dpi=100)
        plt.close(fig)
    except ImportError:
        print("matplotlib missing: no capture.png", file=sys.stderr)
    print("wrote %s (%d samples)" % (path, len(ticks)))


def cmd_identify(d, a):
    """The self-commissioning (docs/commissioning.md): start, wait, the results in SI; with --out
    DIR the same identified.toml and identification.json as `dtc-sil identify` writes."""
    if a.save and not a.apply:
        raise SystemExit2("usage: dtc_console.py --port PATH identify [--json] [--out DIR] [--apply [--save]]")
    try:
        st, res = d.identify(a.timeout)
        ok = True
    except DriveError as e:
        if not isinstance(e.detail, tuple):
            raise
        (st, res), ok, err = e.detail, False, e
    if a.out:
        os.makedirs(a.out, exist_ok=True)
        with open(os.path.join(a.out, "identification.json"), "w", encoding="utf-8") as f:
            json.dump({"status": "ok" if ok else "failed", "drive": st, **res}, f, indent=2)
        with open(os.path.join(a.out, "identified.toml"), "w", encoding="utf-8") as f:
            f.write("# dtc_console.py identify on %s: the firmware's self-commissioning (docs/commissioning.md).\n"
                    "# Use: dtc-sil run SCENARIO --overlay identified.toml\n" % a.port)
            if not ok:
                f.write("# FAILED: %s\n" % err)
            f.write("[firmware]\n")
            done = res["step"] == "done"
            # the steps a failed identification completed: those before the one that failed
            failed_at = {"rs": 1, "ls": 2, "encoder": 3}.get(st["fail_step"], 1) if not ok else 4
            if done or failed_at > 1:
                f.write("rs_ohm = %.6g\ndead_time_s = %.6g\n" % (res["rs_ohm"], res["dead_time_s"]))
            if res.get("machine") == "im":
                # the keys dtc-sil identify writes for an induction machine
                if done:
                    f.write("rr_ohm = %.6g\nlls_h = %.6g\nllr_h = %.6g\nlm_h = %.6g\n" %
                            (res["rr_ohm"], res["lls_h"], res["llr_h"], res["lm_h"]))
                    f.write("pole_pairs = %d\nencoder_reversed = %s\n" %
                            (res["pole_pairs"], "true" if res["encoder_reversed"] else "false"))
                    f.write("j_kgm2 = %.6g\nb_nm_s_per_rad = %.6g\ncoulomb_nm = %.6g\n" %
                            (res["j_kgm2"], max(res["b_nm_s_per_rad"], 0.0), max(res["coulomb_nm"], 0.0)))
            elif done or failed_at > 2:
                f.write("ls_h = %.6g\n" % res["ls_h"])
                if res.get("saliency_ratio"):
                    # L_q when the drive read the machine as salient, else L_d (the surface PM's
                    # model), as dtc-sil identify writes it and IDENT_APPLY applies it
                    f.write("lq_h = %.6g\n" % (res["lq_h"] if res["salient"] else res["ls_h"]))
            if done and res.get("machine") != "im":
                f.write("pole_pairs = %d\nencoder_offset_rad = %.6g\nencoder_reversed = %s\n" %
                        (res["pole_pairs"], res["encoder_offset_rad"], "true" if res["encoder_reversed"] else "false"))
                # friction measured below zero (noise on a frictionless rotor) is written as 0, as dtc-sil does
                f.write("psi_m_wb = %.6g\nj_kgm2 = %.6g\nb_nm_s_per_rad = %.6g\ncoulomb_nm = %.6g\n" %
                        (res["psi_m_wb"], res["j_kgm2"], max(res["b_nm_s_per_rad"], 0.0), max(res["coulomb_nm"], 0.0)))
    if a.json:
        print(json.dumps({"status": "ok" if ok else "failed", "drive": st, **res}, indent=2))
    elif ok and res.get("machine") == "im":
        print("identified: R_s %.4g ohm, R_r %.4g ohm, sigma L_s %.4g H, L_s %.4g H (turning %.4g H), L_m %.4g H, "
              "%d pole pairs%s, J %.4g kg*m^2" % (res["rs_ohm"], res["rr_ohm"], res["sigma_ls_h"], res["ls_h"],
                                                  res["ls_spin_h"], res["lm_h"], res["pole_pairs"],
                                                  ", encoder reversed" if res["encoder_reversed"] else "", res["j_kgm2"]))
    elif ok:
        print("identified: R_s %.4g ohm (slope %.4g), L_s %.4g H, V0 %.4g V, dead time %.3g s, %d pole pairs, "
              "encoder offset %.2f deg (el.)%s" % (res["rs_ohm"], res["r_slope_ohm"], res["ls_h"], res["v0_v"],
                                                   res["dead_time_s"], res["pole_pairs"], res["encoder_offset_el_deg"],
                                                   ", reversed" if res["encoder_reversed"] else ""))
    if not ok:
        raise err
    if a.apply:
        # the printed lines go to stderr under --json (stdout is the identification's JSON)
        out = sys.stderr if a.json else sys.stdout
        n, changed = d.identify_apply()
        for name, was, now in changed:
            print("applied %-28s %14.6g -> %.6g" % (name, was, now), file=out)
        print("applied the identification: %d rows changed%s" % (n, "" if a.save else " (params save stores them)"),
              file=out)
        if a.save:
            print("saved, copy %d" % d.save(), file=out)


def cmd_watch(d, a):
    try:
        while True:
            s = d.status()
            print("\r%-9s %-14s %8.1f rpm %8.4f N*m %7.2f V" % (s["state"], s["fault"], s["speed_rpm"],
                                                                s["torque_est_nm"], s["vdc_v"]), end="", flush=True)
            time.sleep(a.interval)
    except KeyboardInterrupt:
        print()


def main(argv=None):
    p = argparse.ArgumentParser(prog="dtc_console.py", description=__doc__.split("\n\n")[0])
    p.add_argument("--port", required=True, help="serial port (or dtc-sil serve's --serial link)")
    p.add_argument("--baud", type=int, default=115200)
    p.add_argument("--timeout", type=float, default=1.0, help="seconds to wait for each answer (default 1)")
    sub = p.add_subparsers(dest="cmd", required=True)
    s = sub.add_parser("status", help="state, fault, speed, torque")
    s.add_argument("--json", action="store_true")
    sub.add_parser("arm", help="arm (refused unless calibrated, DC link in range, no fault, references zero)")
    sub.add_parser("disarm", help="gates off")
    s = sub.add_parser("speed", help="speed mode with this reference")
    s.add_argument("rpm", type=float)
    s = sub.add_parser("torque", help="torque mode with this reference")
    s.add_argument("nm", type=float)
    sub.add_parser("clear", help="clear a latched fault (the fault log keeps it)")
    s = sub.add_parser("faults", help="the fault log, newest first")
    s.add_argument("--json", action="store_true")
    s = sub.add_parser("params", help="list | get NAME | set NAME VALUE | save | restore [stored|compiled] | export FILE")
    s.add_argument("op", choices=["list", "get", "set", "save", "restore", "export"])
    s.add_argument("args", nargs="*")
    s = sub.add_parser("capture", help="triggered capture to DIR/capture.csv and capture.png")
    s.add_argument("--channels", required=True, help="comma-separated, named as the SIL trace's columns")
    s.add_argument("--samples", type=int, required=True)
    s.add_argument("--trigger", default="now", help="now | fault | above|below|rising|falling:CHANNEL:LEVEL")
    s.add_argument("--pre", type=int, default=0)
    s.add_argument("--decim", type=int, default=1, help="one sample every N ISR periods")
    s.add_argument("--timeout", type=float, default=30.0, help="seconds to wait for the trigger")
    s.add_argument("--out", required=True)
    s = sub.add_parser("identify", help="self-commissioning: R_s, L_s, the inverter's drop, pole pairs, encoder")
    s.add_argument("--json", action="store_true")
    s.add_argument("--out", help="write identified.toml and identification.json here")
    s.add_argument("--timeout", type=float, default=30.0, help="seconds to wait for the end (default 30)")
    s.add_argument("--apply", action="store_true",
                   help="after a successful identification, write its results into the parameters in force")
    s.add_argument("--save", action="store_true", help="with --apply: store the parameters (params save)")
    s = sub.add_parser("watch", help="live status until Ctrl-C")
    s.add_argument("--interval", type=float, default=0.2)
    a = p.parse_args(argv)
    handlers = {
        "status": cmd_status, "faults": cmd_faults, "identify": cmd_identify, "params": cmd_params, "capture": cmd_capture, "watch": cmd_watch,
        "arm": lambda d, _: d.arm(), "disarm": lambda d, _: d.disarm(), "clear": lambda d, _: d.clear(),
        "speed": lambda d, x: d.speed(x.rpm), "torque": lambda d, x: d.torque(x.nm),
    }
    try:
        with Drive(a.port, a.baud, a.timeout) as d:
            handlers[a.cmd](d, a)
    except DriveError as e:
        print("dtc_console: %s" % e, file=sys.stderr)
        return 1
    except SystemExit2 as e:
        print(str(e), file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
