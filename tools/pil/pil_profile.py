#!/usr/bin/env python3
"""pil_profile.py - where the Cortex-M0 instructions of the processor-in-the-loop ISR go, per
function, and the C28x cycle estimate made from that instruction mix (docs/f2812.md, "C28x cycle
estimate").

  pil_profile.py RECORDING [--cm-image ELF] [--top N] [--json OUT] [--ram-cmd CMD] [--period-cycles N]
                 [--detail ISR|worst]... [--capture]

Replays RECORDING (dtc-sil run --record-isr FILE) on qemu-system-arm (mps2-an385, the cross-cm0
PIL image, as pil_compare.py does) with qemu's translation-block log: every translated block's
instructions (-d in_asm) and every block executed (-d exec, with chaining off so that each
execution is logged). Each executed block's instruction count is charged to the function its
first address lies in (the image's symbol table), so the figures are dynamic instruction counts
per function over the whole replay; the listing leaves out the replay harness (HARNESS) and
divides by the app_isr() calls. Each ISR's own figures are the blocks from an entry of
app_isr() to the harness's pil_target_isr_end() (app_isr() and what it calls, up to its return),
harness excluded: the background pass the replay runs after it (app_background, app_get_status)
is not the ISR's. "ISRs that ran the control law" are those that entered law_step. A function's
calls are the executions of its entry block.

The C28x estimate (ESTIMATE: no C28x compiler or simulator is available) re-weights that mix:
  - the libgcc 64-bit helpers (__aeabi_lmul/__muldi3, __aeabi_lasr/__ashrdi3, __aeabi_llsl/
    __ashldi3, __aeabi_llsr/__lshrdi3): Thumb-1 has no 32x32->64 multiply and no 64-bit shift, a
    product takes ~40 instructions; the C28x does the 64-bit product in IMPYL + QMPYL and the
    shift in one LSL64/ASR64: each call is charged C28X_HELPER_CYCLES;
  - the out-of-line IQ helpers the M0 build keeps (iq_mpy: product, rounding, shift and 32-bit
    saturation, IQmath's _IQrsmpy; fix_add32/fix_sub32: the saturating sum): one C28x sequence of
    IQ_MPY_CYCLES / FIX_SAT_CYCLES cycles per call (MOVL XT, IMPYL P, QMPYL ACC, ADDUL/ADDCL,
    MINL/MAXL, LSL64: 20 cycles with LCR/LRETR in TI's IQNrsmpy benchmark, 12 inline; MOVL ACC,
    ADDL with OVM set, MOVL), so their body, the helpers they call and their call/return on the M0
    are replaced by that;
  - every other M0 instruction is charged C28X_CYCLES_PER_INSN cycles: both are single-issue
    in-order machines with a one-cycle ALU path (TI's IQmath benchmarks: about 1 cycle per C28x
    instruction outside calls and branches); the M0 pays more for 32-bit work in 8 registers and
    64-bit sums, the C28x for 16-bit logic, far struct offsets and saturating sums written as
    portable C, and the hand-compiled sample below finds the two about even;
  - every executed block (a straight run of M0 code ending in a branch, a call or a return) is
    charged C28X_BRANCH_EXTRA more cycles: on the C28x's 8-stage pipeline the fast conditional
    branches (BF, SBF) take 4 cycles taken or not, B and SB 7 taken and 4 not, LCR and LRETR 4
    each (SPRU430, TI's C28x workshop), against the one counted for its M0 instruction.
  The weights are printed with the figure so that the reader can scale them.

  A second figure scales that estimate by HAND_SAMPLE: a few hot functions of the PM ISR written
  out by hand in C28x assembly the way cl2000 -O2 would plausibly compile them (docs/c28x-sample.md),
  their cycles on the path the PIL runs against what the weights charge for the same path. It is
  printed twice: for the C as written (portable saturating sums) and with the saturating sums as
  ADDL under the C28x's overflow mode. A hand estimate of six functions, not a compiler's output.

With --capture the image attaches and arms a capture for the whole replay (target/pil/pil_cm_main.c:
four channels every period, a trigger that never fires), so every ISR carries the capture's longest
per-period path, as on a drive whose host records a capture.

With --ram-cmd CMD (a linker command file that places functions by name, `*(.text:_NAME)`, as
linker/f2812_flash_im.cmd does), every function CMD does not name runs from flash, and each of
its executed M0 instructions is charged FLASH_WAIT_PER_INSN more cycles: the F2812's flash at
150 MHz with RANDWAIT = PAGEWAIT = 5 (fact sheet 4.7), taken pessimistically as one random-access
fetch per instruction (the flash pipeline's prefetch ignored). The listing marks those functions
and sums their wait cycles per ISR: from app_isr()'s entry to the harness's pil_target_isr_end()
(the background the replay runs after it is not the ISR's). The out-of-line helpers (64-bit
helpers, iq_mpy, the saturating adds) are single C28x sequences inlined by cl2000 into their
caller: they run where the caller runs; the HAL's functions (hal_*: the replay HAL here) are the
F2812 HAL's ramfuncs (F2812_RAMFUNC) on the target.
"""
import argparse
import bisect
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))

HELPERS = {"__aeabi_lmul", "__muldi3", "__aeabi_lasr", "__ashrdi3", "__aeabi_llsl", "__ashldi3",
           "__aeabi_llsr", "__lshrdi3"}
IQ_MPY = {"iq_mpy"}
FIX_SAT = {"fix_add32", "fix_sub32"}
HARNESS = re.compile(r"^(main|pil_|semi_|put(16|32)|get(16|32)|flush_|hal_replay_|_|memset|memcpy|Reset_Handler|SysTick)")
C28X_CYCLES_PER_INSN = 1.0
C28X_BRANCH_EXTRA = 3
C28X_HELPER_CYCLES = 4
IQ_MPY_CYCLES = 12
FIX_SAT_CYCLES = 4
FLASH_WAIT_PER_INSN = 5

# The hand-compiled sample (docs/c28x-sample.md): per function, its Cortex-M0 path per call in the
# PIL (self instructions, executed blocks, calls of the 64-bit product helper, of iq_mpy and of the
# out-of-line saturating sums; pil_profile.py --json, "functions"), and the C28x cycles of the hand
# listing for the C as written and with the saturating sums as ADDL under the overflow mode.
HAND_SAMPLE = (
    # name,            instr, blocks, products, iq_mpy, sat sums, hand (C as written), hand (OVM)
    ("app_adc_to_pu",      9,      3,        1,      0,        0,                   21,         21),
    ("dtc_pol_mid",       33,      3,        0,      0,        2,                   61,         37),
    ("vrec_from_legs",    46,      7,        2,      0,        2,                   71,         33),
    ("check_trips",       41,      7,        0,      0,        0,                   64,         64),
    ("q32_integrate",     27,      4,        1,      0,        1,                   42,         31),
    # iq_mpy is charged as one sequence (its 20 M0 instructions, 3 blocks and product as one iq_mpy)
    ("iq_mpy",             0,      0,        0,      1,        0,                   19,         19),
)


def ram_functions(cmd):
    """Names of the functions a linker command file places by name (`.text:_NAME`, COFF)."""
    with open(cmd) as f:
        text = re.sub(r"/\*.*?\*/", "", f.read(), flags=re.S)
    return set(re.findall(r"\.text:_([A-Za-z0-9_]+)", text))


def symbols(elf):
    """Sorted (address, name) of the image's functions (Thumb bit cleared)."""
    out = subprocess.run(["arm-none-eabi-nm", "-n", elf], capture_output=True, text=True, check=True).stdout
    syms = []
    for line in out.splitlines():
        p = line.split()
        if len(p) == 3 and p[1] in "tTwW":
            syms.append((int(p[0], 16) & ~1, p[2]))
    syms.sort()
    return syms


def block_cycles(name, n, is_entry):
    """C28x cycles charged for one executed M0 block of n instructions in function name."""
    if name in HELPERS:
        return C28X_HELPER_CYCLES if is_entry else 0
    if name in IQ_MPY:  # its __aeabi_lmul call is charged as a helper call
        return IQ_MPY_CYCLES - C28X_HELPER_CYCLES if is_entry else 0
    if name in FIX_SAT:
        return FIX_SAT_CYCLES if is_entry else 0
    return n * C28X_CYCLES_PER_INSN + C28X_BRANCH_EXTRA


def weighted_cycles(instr, blocks, products, iq_mpys, sat_sums):
    """What the weights charge for one call's M0 path: its own instructions and blocks, and the
    helpers it calls (block_cycles summed over that path)."""
    return (instr * C28X_CYCLES_PER_INSN + blocks * C28X_BRANCH_EXTRA + products * C28X_HELPER_CYCLES
            + iq_mpys * IQ_MPY_CYCLES + sat_sums * FIX_SAT_CYCLES)


def hand_ratios(sample=HAND_SAMPLE):
    """(hand cycles / weighted cycles) summed over the sample: for the C as written, and with the
    saturating sums under the overflow mode."""
    weighted = sum(weighted_cycles(*row[1:6]) for row in sample)
    return sum(row[6] for row in sample) / weighted, sum(row[7] for row in sample) / weighted


def flash_wait(name, n, ram):
    """Wait cycles of one executed block of n M0 instructions of function name; ram None: all RAM."""
    # gcc's clones (NAME.isra.N, NAME.constprop.N) are the .cmd's NAME, as budget.sh counts them
    if (ram is None or name.split(".")[0] in ram or name in HELPERS or name in IQ_MPY or name in FIX_SAT
            or name.startswith("hal_")):
        return 0
    return n * FLASH_WAIT_PER_INSN


def profile(rec, elf, ram=None, capture=False):
    """{function: [instructions, calls, blocks, instructions from flash in the ISR, instructions
    in the ISR, calls in the ISR]} over the replay (in the ISR: from app_isr's entry to
    pil_target_isr_end's), and per ISR (from each entry of app_isr to pil_target_isr_end's) the
    ISR path's M0 instructions and C28x cycles (harness excluded)."""
    qemu = shutil.which("qemu-system-arm")
    if qemu is None:
        raise SystemExit("pil_profile: qemu-system-arm not found (tools/setup.sh installs it)")
    syms = symbols(elf)
    addrs = [a for a, _ in syms]
    entry = {a for a, _ in syms}
    tb_len = {}
    per = {}
    isr_m0, isr_c28, isr_law, isr_wait, isr_fn = [], [], [], [], []
    with tempfile.TemporaryDirectory() as d:
        shutil.copyfile(rec, os.path.join(d, "pil_in.bin"))
        if capture:
            open(os.path.join(d, "pil_capture.bin"), "wb").close()  # the image arms its capture
        fifo = os.path.join(d, "log")
        os.mkfifo(fifo)
        p = subprocess.Popen([qemu, "-M", "mps2-an385", "-nographic", "-monitor", "none", "-serial", "none",
                              "-d", "in_asm,exec,nochain", "-D", fifo,
                              "-semihosting-config", "enable=on,target=native", "-kernel", elf], cwd=d)
        cur_pc, cur_n = None, 0
        in_isr = False
        with open(fifo, errors="replace") as f:
            for line in f:
                if line.startswith("Trace "):
                    m = re.search(r"\[[0-9a-f]+/([0-9a-f]+)/", line)
                    if not m:
                        continue
                    pc = int(m.group(1), 16)
                    n = tb_len.get(pc, 0)
                    i = bisect.bisect_right(addrs, pc) - 1
                    name = syms[i][1] if i >= 0 else "?"
                    if pc in entry and name in ("app_isr", "pil_target_isr_end"):
                        in_isr = name == "app_isr"
                    e = per.setdefault(name, [0, 0, 0, 0, 0, 0])
                    e[0] += n
                    e[2] += 1
                    if in_isr:
                        e[4] += n
                    if pc in entry:
                        e[1] += 1
                        if in_isr:
                            e[5] += 1
                        if name == "app_isr":
                            isr_m0.append(0)
                            isr_c28.append(0.0)
                            isr_law.append(False)
                            isr_wait.append(0)
                            isr_fn.append({})
                        elif name == "law_step" and isr_law:
                            isr_law[-1] = True
                    if isr_m0 and in_isr and (not HARNESS.match(name) or name in HELPERS):
                        isr_m0[-1] += n
                        w = flash_wait(name, n, ram)
                        cyc = block_cycles(name, n, pc in entry) + w
                        isr_c28[-1] += cyc
                        isr_wait[-1] += w
                        f_isr = isr_fn[-1].setdefault(name, [0, 0.0])
                        f_isr[0] += n
                        f_isr[1] += cyc
                        if w:
                            e[3] += n  # instructions run from flash inside the ISR
                elif line.startswith("IN:"):
                    cur_pc, cur_n = None, 0
                elif line.startswith("0x"):
                    m = re.match(r"0x([0-9a-f]+):", line)
                    if m:
                        if cur_pc is None:
                            cur_pc = int(m.group(1), 16)
                        cur_n += 1
                        tb_len[cur_pc] = cur_n
        if p.wait() != 0:
            raise SystemExit("pil_profile: qemu failed")
    return per, isr_m0, isr_c28, isr_law, isr_wait, isr_fn


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("recording")
    ap.add_argument("--cm-image", default=os.path.join(ROOT, "build", "cross-cm0", "bin", "pil_cm.elf"))
    ap.add_argument("--top", type=int, default=25)
    ap.add_argument("--json")
    ap.add_argument("--period-cycles", type=int, default=7500,
                    help="C28x cycles of the control period at 150 MHz (7500: 50 us; 6000: 40 us)")
    ap.add_argument("--ram-cmd", help="linker command file naming the functions in zero-wait RAM; "
                    "the others are charged flash wait states")
    ap.add_argument("--detail", action="append", default=[], metavar="ISR",
                    help="print the M0 instructions and C28x cycles per function of this ISR (an index, or "
                         "'worst': the worst C28x ISR and the two after it); repeatable")
    ap.add_argument("--capture", action="store_true",
                    help="replay with a capture armed for the whole run (four channels every period)")
    a = ap.parse_args()
    ram = ram_functions(a.ram_cmd) if a.ram_cmd else None
    per, isr_m0, isr_c28, isr_law, isr_wait, isr_fn = profile(a.recording, a.cm_image, ram, a.capture)
    if a.capture and "capture_isr_run" not in per:
        raise SystemExit("pil_profile: --capture: the image ran no capture (an image without it?)")
    count = len(isr_m0)
    if count == 0:
        raise SystemExit("pil_profile: no app_isr call in the replay")
    rows = sorted(((v[0], v[1], v[2], k) for k, v in per.items() if not HARNESS.match(k) or k in HELPERS),
                  reverse=True)
    print("  Cortex-M0 instructions per ISR by function (qemu block log, %d ISRs; self, not inclusive):" % count)
    for n, calls, _, k in rows[:a.top]:
        print("    %-26s %8.1f instr/ISR %6.2f calls/ISR%s" % (k, n / count, calls / count,
              "  (flash)" if flash_wait(k, 1, ram) else ""))
    m0_mean, c28_mean = sum(isr_m0) / count, sum(isr_c28) / count
    w = max(range(count), key=lambda k: isr_c28[k])
    print("  ISR path (app_isr() to its return; replay harness and background excluded), Cortex-M0 instructions:"
          " mean %.0f, worst %d" % (m0_mean, max(isr_m0)))
    print("  C28x ESTIMATE from the weights, cycles (%.1f per M0 instruction, +%d per block, %d per 64-bit helper call,"
          % (C28X_CYCLES_PER_INSN, C28X_BRANCH_EXTRA, C28X_HELPER_CYCLES))
    print("    %d per iq_mpy, %d per saturating add; docs/f2812.md): mean %.0f, worst %.0f (ISR %d) = %.0f %% of"
          " the %d-cycle period; %.2f C28x cycles per M0 instruction"
          % (IQ_MPY_CYCLES, FIX_SAT_CYCLES, c28_mean, isr_c28[w], w, 100.0 * isr_c28[w] / a.period_cycles,
             a.period_cycles,
             c28_mean / m0_mean if m0_mean else 0.0))
    r_c, r_ovm = hand_ratios()
    print("  C28x ESTIMATE from the hand-compiled sample (docs/c28x-sample.md: its hand cycles are x%.2f the weights'"
          " for the C as written,\n    x%.2f with the saturating sums as ADDL under OVM): mean %.0f / %.0f, worst %.0f / %.0f"
          " = %.0f / %.0f %% (a hand estimate of %d functions, +-30 %%)"
          % (r_c, r_ovm, r_c * c28_mean, r_ovm * c28_mean, r_c * isr_c28[w], r_ovm * isr_c28[w],
             100.0 * r_c * isr_c28[w] / a.period_cycles, 100.0 * r_ovm * isr_c28[w] / a.period_cycles,
             len(HAND_SAMPLE)))
    if ram is not None:
        wf = max(range(count), key=lambda k: isr_wait[k])
        flash = sorted(((v[3], k) for k, v in per.items()
                        if (not HARNESS.match(k) or k in HELPERS) and flash_wait(k, 1, ram) and v[3]), reverse=True)
        print("  flash wait states (%s: functions not named there run from flash, +%d cycles per M0 instruction,"
              " pessimistic): mean %.0f, worst %d cycles per ISR (ISR %d), included above"
              % (os.path.relpath(a.ram_cmd), FLASH_WAIT_PER_INSN, sum(isr_wait) / count, isr_wait[wf], wf))
        print("    executed from flash: %s" % (", ".join("%s %.1f" % (k, n / count) for n, k in flash[:12]) or "none"))
    run = [k for k in range(count) if isr_law[k]]
    if run:
        wr = max(run, key=lambda k: isr_c28[k])
        print("    ISRs that ran the control law (%d): M0 mean %.0f, worst %d; C28x mean %.0f, worst %.0f (ISR %d) = %.0f %%"
              % (len(run), sum(isr_m0[k] for k in run) / len(run), max(isr_m0[k] for k in run),
                 sum(isr_c28[k] for k in run) / len(run), isr_c28[wr], wr, 100.0 * isr_c28[wr] / a.period_cycles))
        print("      from the hand-compiled sample: worst %.0f = %.0f %% as written, %.0f = %.0f %% with ADDL under OVM"
              % (r_c * isr_c28[wr], 100.0 * r_c * isr_c28[wr] / a.period_cycles,
                 r_ovm * isr_c28[wr], 100.0 * r_ovm * isr_c28[wr] / a.period_cycles))
    detail = []
    for x in a.detail:
        detail += [w, w + 1, w + 2] if x == "worst" else [int(x)]
    for k in detail:
        if 0 <= k < count:
            print("  ISR %d: M0 %d, C28x %.0f (%.0f %%); per function, M0 instructions / C28x cycles:"
                  % (k, isr_m0[k], isr_c28[k], 100.0 * isr_c28[k] / a.period_cycles))
            for name, (n, cyc) in sorted(isr_fn[k].items(), key=lambda kv: -kv[1][1]):
                print("    %-26s %6d %8.0f" % (name, n, cyc))
    if a.json:
        with open(a.json, "w") as f:
            json.dump({"isrs": count, "m0_mean": m0_mean, "m0_worst": max(isr_m0), "c28x_mean": c28_mean,
                       "c28x_worst": isr_c28[w], "c28x_hand_ratio": r_c, "c28x_hand_ratio_ovm": r_ovm,
                       "isr_m0": isr_m0, "isr_c28x": isr_c28, "isr_law": isr_law,
                       "functions": per}, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
