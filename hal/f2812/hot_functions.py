#!/usr/bin/env python3
"""hot_functions.py - which functions of an F2812 flash image run from zero-wait RAM, chosen by
measurement, written into the linker command file that places them by name (linker/
f2812_flash.cmd for the PM image dtc_f2812, linker/f2812_flash_im.cmd for the IM image
dtc_f2812_im).

  hot_functions.py --image pm|im [--pil JSON]... [--root DIR] [--sil EXE] [--cm0 DIR] [--write]

1. Measures: runs the image's shipped scenarios (IMAGES below: the PM law's on both topologies
   with both estimators and the measured mid-point; the IM speed scenario, standstill,
   magnetisation, acceleration to 1000 rpm and the step to rated load, once per IM scheme) under
   valgrind's callgrind with collection inside app_isr() only: each function's own instructions
   and calls per ISR on the host build (dtc-sil).
   With --pil JSON (tools/pil/pil_profile.py --json on a dtc-sil --record-isr recording): the
   Cortex-M0 image's own calls per ISR inside app_isr() as well, which see the functions the
   host inlines (and those called through a pointer).
2. A function is hot when some run calls it at least HOT_CALLS_PER_ISR times per ISR (the
   per-period path and the speed loop; not the start-up's one-off steps, the fault paths or the
   background). Its weight is what it would cost from flash in an ISR that runs it: its
   instructions in such an ISR (per ISR, or per call when it runs less than once per ISR: the
   speed loop's ISR is the worst one) times the run's ISRs per second, the largest over the runs.
3. Maps them onto the image the linker sees (the image's application in the cross-cm0 build, as
   hal/f2812/budget.sh links it): the host inlines static functions the Cortex-M0 build keeps, so
   every function of the image that a hot function calls (its `bl` targets, transitively) is hot
   too, unless the host build has it as a function of its own that the measurement found cold (a
   rare branch: a fault, a limit, a hand-over).
   With --pil, what the replay's ISRs call less often than that (the entry to RUN: the law's
   reset, its first period's speed-measurement reset) is RARE: placed after every hot function,
   where room is left, because the worst ISR counts, not only the mean. The operation layer's ISR
   part (OPS_ISR: the capture's recording, the fault log's record) is placed first, in ramfuncs, on
   the PM image ("ops": "first"); on the IM image, whose blocks the hot path nearly fills, right
   after the hot functions and before the rare ones ("after_hot": placed first, it pushed the law's
   hot functions to flash, worst IM ISR 95 -> 119 %; after the rare ones, it found no room left and
   an armed capture ran from flash, 111 %; both measured).
4. Fills the blocks in order of weight per word (the wait states saved per word of RAM), each up
   to the image's fill of its words by the pessimistic size (Thumb bytes / 2 * 1.5, counted as
   budget.sh counts it: the copies in the archives cl2000 splits by function): ramfuncs_h (H0's
   code part) first, then ramfuncs_m (M1), then ramfuncs (L0+L1, less what budget.sh adds there,
   measured on the image: the control tables and the HAL's ramfuncs). What does not fit
   stays in flash; the script prints it with the host instructions per ISR left in flash, and
   tools/pil/pil_profile.py --ram-cmd counts their wait states per ISR on the Cortex-M0 replay.

--write replaces the lists between the markers `hot:SECTION begin` and `hot:SECTION end` of the
.cmd; without it the lists are printed. Run it after a change to a law or the application
(budget.sh fails on a name the image no longer defines).
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile

HOT_CALLS_PER_ISR = 0.01   # at least once per 100 control periods (the speed loop runs every few)
MARGIN = 0.95              # budget.sh's margin: the most of a block any image fills
FLASH_WAIT = 5             # RANDWAIT = PAGEWAIT = 5 at 150 MHz (fact sheet 4.7), per fetch
# Per image: its linker command file, its application archives and main object (cross-cm0), and
# the runs measured (scenario, dtc-sil --set overrides).
# "fill": the part of each zero-wait block the hot lists may take. The PM image stops at 85 %
# (the lean 50 us path's room for what the board adds: every hot function of its five runs fits
# with it, none left in flash); the IM image needs up to budget.sh's 95 % (at 85 % SFVC's and
# DFOC's steps would run from flash, ~2,000 wait cycles per ISR).
IMAGES = {
    "pm": {"cmd": "f2812_flash.cmd", "fill": 0.85, "ops": "first", "app": "libdtc_app", "proto": "libdtc_proto", "main": "f2812_main.dir",
           "runs": [(sc, ()) for sc in ("fstp_voltage_proposed_full", "fstp_current_full", "sstp_voltage_simple_full",
                                        "sstp_current_full", "fstp_voltage_simple_full_midpoint")]},
    "im": {"cmd": "f2812_flash_im.cmd", "fill": MARGIN, "ops": "after_hot", "app": "libdtc_app_im", "proto": "libdtc_proto_im",
           "main": "f2812_main_im.dir",
           "runs": [("im_dtc_speed", ('control.scheme="%s"' % s, "duration_s=1.5"))
                    for s in ("dtc", "dsc", "sfvc", "dfoc", "dsvm")]},
}
# The operation layer's ISR part (libdtc_comm.a, capture.c and faultlog.c): the capture's per-period
# recording (app_core_step calls capture_isr_run while a capture is armed or triggered) and the
# fault log's record (at a fault), with what they call: the hot list is measured without a capture,
# and a capture may be armed at any time, so the image's zero-wait RAM budget counts them in. On the
# PM image ("first") placed first, in ramfuncs (L0+L1); on the IM image ("after_hot") after its hot
# functions, before the rare entry functions (an armed capture runs in every ISR, the entry to RUN
# in one: docs/f2812.md).
OPS_ISR = ("capture_isr_run", "faultlog_record")
OPS_ISR_MEMBERS = ("capture.c.obj", "faultlog.c.obj")
SECTIONS = ("ramfuncs_h", "ramfuncs_m", "ramfuncs")  # filled in this order (.cmd MEMORY RAMH0P, RAMM1P, RAML0L1)
HELPERS = re.compile(r"^(__aeabi_|__.*di3$)")  # libgcc: single C28x instructions, not placed


def run(cmd, **kw):
    return subprocess.run(cmd, check=True, capture_output=True, text=True, **kw).stdout


def callgrind_profile(sil, scenario, sets, tmp):
    """{function: (instructions, calls)} per ISR inside app_isr, and ISRs per second."""
    out = os.path.join(tmp, "cg.out")
    cmd = ["nice", "valgrind", "--tool=callgrind", "--toggle-collect=app_isr", "--callgrind-out-file=" + out,
           sil, "run", scenario, "--out", os.path.join(tmp, "run")]
    for x in sets:
        cmd += ["--set", x]
    res = subprocess.run(cmd, capture_output=True, text=True)
    if res.returncode != 0:
        raise SystemExit("hot_functions: %s failed: %s" % (" ".join(cmd[5:]), res.stderr[-400:]))
    m = re.search(r"simulated ([0-9.]+) s in .*?, ([0-9]+) ISRs", res.stdout)
    if not m:
        raise SystemExit("hot_functions: no ISR count in dtc-sil's output (%s)" % scenario)
    seconds, isrs = float(m.group(1)), int(m.group(2))
    names, own, calls = {}, {}, {}
    fn = cfn = None
    pending_calls = False
    with open(out) as f:
        for line in f:
            m = re.match(r"^(c?fn)=\((\d+)\)(?: (.*))?$", line.rstrip("\n"))
            if m:
                if m.group(3):
                    names[m.group(2)] = m.group(3)
                name = names.get(m.group(2), "?")
                if m.group(1) == "fn":
                    fn = name
                else:
                    cfn = name
                continue
            if line.startswith("calls="):
                calls[cfn] = calls.get(cfn, 0) + int(line.split()[0][6:])
                pending_calls = True
                continue
            m = re.match(r"^(?:[+-]?\d+|\*) (\d+)$", line.strip())
            if m:
                if pending_calls:  # the cost line of a call: inclusive, the callee's
                    pending_calls = False
                else:
                    own[fn] = own.get(fn, 0) + int(m.group(1))
    prof = {k: (own.get(k, 0) / isrs, calls.get(k, 0) / isrs) for k in set(own) | set(calls)}
    return prof, isrs / seconds


def image_functions(cm0, img, tmp, root):
    """{name: bytes} of the image's control functions, {name: set of callees}, and the words of
    L0+L1 that budget.sh adds to ramfuncs beside the hot list (the control tables, nominal, and
    the HAL's ramfuncs, pessimistic), cross-cm0.

    A function's bytes are counted as hal/f2812/budget.sh counts them: over the members the image
    links of the archives cl2000 compiles with --gen_func_subsections (the control archives and,
    of libdtc_comm.a, the ISR part OPS_ISR_MEMBERS), gcc's local copies of one name (a static
    inline helper kept out of line in several objects) summed. The `*(.text:_NAME)` rules of the
    .cmd claim exactly those copies; a copy in the init, configuration or background archives
    (compiled without subsections) stays in their .text, in flash."""
    fw = os.path.join(cm0, "firmware")
    app = img["app"] if os.path.exists(os.path.join(fw, img["app"] + ".a")) else "libdtc_app"
    main_dir = img["main"] if app == img["app"] else "f2812_main.dir"
    main = os.path.join(cm0, "target", "f2812", "CMakeFiles", main_dir, "f2812_main.c.obj")
    hal = os.path.join(cm0, "hal", "f2812", "libhal_f2812.a")
    allo = os.path.join(tmp, "all.o")
    libs = [hal] + [
        os.path.join(fw, a + ".a") for a in (app, app + "_init", "libdtc_init", "libdtc_im", "libdtc_firmware",
                                             "libdtc_config", "libdtc_fixmath", "libdtc_comm")]
    libs.append(os.path.join(fw, (img["proto"] if app == img["app"] else "libdtc_proto") + ".a"))
    link_map = run(["arm-none-eabi-ld", "-r", "-M", "-o", allo, main, "--start-group"] + libs + ["--end-group"])
    control = (app, "libdtc_im", "libdtc_firmware", "libdtc_fixmath")
    linked = {a: set(re.findall(r"%s\.a\(([A-Za-z0-9_.]+)\)" % re.escape(a), link_map))
              for a in control + ("libdtc_comm",)}
    linked["libdtc_comm"] &= set(OPS_ISR_MEMBERS)
    size = {}
    for a in control + ("libdtc_comm",):
        for line in run(["arm-none-eabi-nm", "-S", "-t", "d", "-A", os.path.join(fw, a + ".a")]).splitlines():
            p = line.split()
            if len(p) == 4 and p[2] in "tT" and p[0].split(":")[-2] in linked[a]:
                name = p[3].split(".")[0]
                size[name] = size.get(name, 0) + int(p[1])
    # budget.sh's other words in ramfuncs: every control table (.rodata of the control archives'
    # linked members, nominal words) and the HAL's F2812_RAMFUNC functions (pessimistic words)
    table_bytes = 0
    for a in control:
        member = None
        for line in run(["arm-none-eabi-size", "-A", os.path.join(fw, a + ".a")]).splitlines():
            m = re.match(r"^(\S+)\s+\(ex ", line)
            if m:
                member = m.group(1)
                continue
            p = line.split()
            if len(p) >= 2 and p[0].startswith(".rodata") and member in linked[a]:
                table_bytes += int(p[1])
    ramfunc_names = set()
    for d in (os.path.join(root, "hal", "f2812"), os.path.join(root, "target", "f2812")):
        for fn in sorted(os.listdir(d)):
            if fn.endswith(".c"):
                with open(os.path.join(d, fn)) as f:
                    ramfunc_names |= set(re.findall(r"F2812_RAMFUNC\(([a-z0-9_]+)\)", f.read()))
    hal_bytes = sum(int(p[1]) for p in (l.split() for l in run(["arm-none-eabi-nm", "-S", "-t", "d", hal, main])
                                          .splitlines()) if len(p) == 4 and p[3] in ramfunc_names)
    reserve = (table_bytes + 1) // 2 + pess_words(hal_bytes)
    callees = {}
    cur_obj = None
    for line in run(["arm-none-eabi-objdump", "-dr", allo]).splitlines():
        m = re.match(r"^[0-9a-f]+ <([A-Za-z0-9_.]+)>:$", line)
        if m:
            cur_obj = m.group(1).split(".")[0]
            callees.setdefault(cur_obj, set())
            continue
        m = re.search(r"\bbl\s+[0-9a-f]+ <([A-Za-z0-9_.]+?)(?:\+0x[0-9a-f]+)?>", line) or \
            re.search(r"R_ARM_THM_CALL\s+([A-Za-z0-9_.]+)", line)
        if m and cur_obj:
            callees[cur_obj].add(m.group(1).split(".")[0])
    return size, callees, reserve


def host_functions(sil):
    return {p[2] for p in (l.split() for l in run(["nm", sil]).splitlines()) if len(p) == 3 and p[1] in "tT"}


def cmd_words(cmd_text, block):
    m = re.search(r"^\s*%s\s*:\s*origin\s*=\s*0x[0-9A-Fa-f]+,\s*length\s*=\s*(0x[0-9A-Fa-f]+)" % block,
                  cmd_text, re.M)
    if not m:
        raise SystemExit("hot_functions: no MEMORY block %s in linker/f2812_flash_mem.cmd" % block)
    return int(m.group(1), 16)


def pess_words(nbytes):
    return (nbytes * 3 + 3) // 4


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--root", default=os.path.normpath(os.path.join(here, "..", "..")))
    ap.add_argument("--sil")
    ap.add_argument("--cm0")
    ap.add_argument("--write", action="store_true")
    ap.add_argument("--image", choices=sorted(IMAGES), required=True)
    ap.add_argument("--pil", action="append", default=[], metavar="JSON",
                    help="pil_profile.py --json output of a replay of this image's law")
    a = ap.parse_args()
    img = IMAGES[a.image]
    sil = a.sil or os.path.join(a.root, "build", "host", "bin", "dtc-sil")
    cm0 = a.cm0 or os.path.join(a.root, "build", "cross-cm0")
    cmd_path = os.path.join(a.root, "linker", img["cmd"])
    with open(cmd_path) as f:
        cmd_text = f.read()
    with open(os.path.join(a.root, "linker", "f2812_flash_mem.cmd")) as f:
        mem_text = f.read()
    runs = ["%s%s" % (sc, "".join(" " + x.split("=")[1].strip('"') for x in sets[:1])) for sc, sets in img["runs"]]
    with tempfile.TemporaryDirectory() as tmp:
        weight, hot_host, seen, profs = {}, set(), set(), {}
        for label, (sc, sets) in zip(runs, img["runs"]):
            prof, rate = callgrind_profile(sil, os.path.join(a.root, "tools", "scenarios", sc + ".toml"), sets, tmp)
            profs[label] = (prof, rate)
            for name, (ir, calls) in prof.items():
                seen.add(name)
                if calls >= HOT_CALLS_PER_ISR:
                    hot_host.add(name)
                    weight[name] = max(weight.get(name, 0.0), ir / min(calls, 1.0) * rate)
        size, callees, reserve = image_functions(cm0, img, tmp, a.root)
    host = host_functions(sil)
    # the Cortex-M0 replays: calls per ISR inside app_isr (pil_profile.py: from its entry to the
    # harness's end of the ISR); weight at 25,000 ISRs/s (the fastest period)
    rare = set()
    for path in a.pil:
        with open(path) as f:
            pil = json.load(f)
        for name, v in pil["functions"].items():
            instr, calls = v[4], v[5]  # inside the ISR
            name = name.split(".")[0]
            if name in size and calls / pil["isrs"] >= HOT_CALLS_PER_ISR:
                hot_host.add(name)
                weight[name] = max(weight.get(name, 0.0),
                                   instr / pil["isrs"] / min(calls / pil["isrs"], 1.0) * 25000.0)
            elif name in size and calls > 0:
                rare.add(name)  # once in a while (the entry to RUN, the law's first period): RARE
                weight[name] = max(weight.get(name, 0.0), instr / calls * 25000.0)
    # the operation layer's ISR part and what it calls on the image (OPS_ISR), whatever the runs
    # measured: placed first, in ramfuncs (PM, "ops" "first"), or right after the hot functions,
    # before the rare ones (IM, "after_hot")
    ops = {n for n in OPS_ISR if n in size}
    todo = sorted(ops)
    while todo:
        for c in sorted(callees.get(todo.pop(), ())):
            if c in size and not HELPERS.match(c) and c not in ops:
                ops.add(c)
                todo.append(c)
    # closure over the image's call graph; a function the host inlined takes the largest weight of
    # its hot callers (iterated to the fixed point, so the result does not depend on the order)
    hot = {n for n in hot_host if n in size and n not in ops}
    changed = True
    while changed:
        changed = False
        for f in sorted(hot):
            for c in sorted(callees.get(f, ())):
                if c not in size or HELPERS.match(c) or c in ops or (c in host and c not in hot_host):
                    continue  # not placed, or a function of its own on the host too, measured cold
                if c not in hot_host and weight.get(c, 0.0) < weight.get(f, 0.0):
                    weight[c] = weight.get(f, 0.0)
                    changed = True
                if c not in hot:
                    hot.add(c)
                    changed = True
    # RARE: what the replay's ISRs call less often than the hot threshold, and what that calls on
    # the image (not the host's cold functions): placed after every hot function, where room is left
    rare -= hot | ops
    todo = sorted(rare)
    while todo:
        f = todo.pop()
        for c in sorted(callees.get(f, ())):
            if c in size and not HELPERS.match(c) and c not in hot and c not in ops and c not in rare:
                rare.add(c)
                weight[c] = max(weight.get(c, 0.0), weight.get(f, 0.0))
                todo.append(c)
    # the most instructions per second saved from the wait states per word of RAM first
    order = sorted(hot, key=lambda n: (-weight.get(n, 0.0) / max(size[n], 1), n))
    order_rare = sorted(rare, key=lambda n: (-weight.get(n, 0.0) / max(size[n], 1), n))
    fill = img["fill"]
    cap = {"ramfuncs_h": int(cmd_words(mem_text, "RAMH0P") * fill),
           "ramfuncs_m": int(cmd_words(mem_text, "RAMM1P") * fill),
           "ramfuncs": int(cmd_words(mem_text, "RAML0L1") * fill) - reserve}
    first = img["ops"] == "first"
    place = {"ramfuncs_h": [], "ramfuncs_m": [], "ramfuncs": sorted(ops) if first else [], "flash": []}
    used = {"ramfuncs_h": 0, "ramfuncs_m": 0, "ramfuncs": sum(pess_words(size[n]) for n in ops) if first else 0}
    for n in order + ([] if first else sorted(ops)) + order_rare:
        w = pess_words(size[n])
        for sect in SECTIONS:
            if used[sect] + w <= cap[sect]:
                place[sect].append(n)
                used[sect] += w
                break
        else:
            place["flash"].append(n)
    print("hot functions (host callgrind, %s; >= %.2f calls/ISR in some run, plus their callees on the "
          "Cortex-M0): %d, %d words pessimistic" % ("; ".join(runs), HOT_CALLS_PER_ISR, len(order),
                                                    sum(pess_words(size[n]) for n in order)))
    print("  the operation layer's ISR part (%s): %s, %d words pessimistic"
          % ("first, in ramfuncs" if first else "after the hot functions, before the rare ones",
             " ".join(sorted(ops)) or "none", sum(pess_words(size[n]) for n in ops)))
    print("  ramfuncs' other words (budget.sh: the control tables and the HAL's ramfuncs): %d" % reserve)
    print("  rare in the Cortex-M0 replays' ISRs (placed after the hot ones, where room is left): %s, %d words "
          "pessimistic" % (" ".join(order_rare) or "none", sum(pess_words(size[n]) for n in order_rare)))
    for sect in SECTIONS:
        print("  %-10s %5d words pessimistic of %d: %s" % (sect, used[sect], cap[sect], " ".join(place[sect])))
    print("  hot but in flash (no room): %s" % (" ".join(place["flash"]) or "none"))
    ram = set(place["ramfuncs_h"]) | set(place["ramfuncs_m"]) | set(place["ramfuncs"])
    print("  host instructions per ISR outside these lists (x %d wait cycles each from flash, pessimistic):"
          % FLASH_WAIT)
    for s in runs:
        prof, rate = profs[s]
        fl = sum(ir for n, (ir, _) in prof.items() if n in size and n not in ram)
        print("    %-30s %7.1f of %7.1f (%.0f ISRs/s): ~%.0f wait cycles per ISR"
              % (s, fl, sum(ir for n, (ir, _) in prof.items() if n in size), rate, fl * FLASH_WAIT))
    cold = sorted(n for n in size if n not in hot and n not in ops and n not in rare)
    print("  the image's other control functions, in flash: %d, %d words pessimistic"
          % (len(cold), sum(pess_words(size[n]) for n in cold)))
    if a.write:
        text = cmd_text
        for sect in SECTIONS:
            body = "".join("                    *(.text:_%s)\n" % n for n in sorted(place[sect]))
            pat = re.compile(r"(/\* hot:%s begin[^\n]*\n)(.*?)([ \t]*/\* hot:%s end \*/)" % (sect, sect), re.S)
            if not pat.search(text):
                raise SystemExit("hot_functions: no hot:%s markers in %s" % (sect, cmd_path))
            text = pat.sub(lambda m: m.group(1) + body + m.group(3), text)
        with open(cmd_path, "w") as f:
            f.write(text)
        print("wrote %s" % cmd_path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
