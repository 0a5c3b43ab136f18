#!/usr/bin/env python3
"""The C28x estimate's weights and its hand-compiled sample (tools/pil/pil_profile.py,
docs/c28x-sample.md), without qemu:

- block_cycles charges what docs/f2812.md says: a 64-bit product helper call C28X_HELPER_CYCLES,
  an iq_mpy call with its product IQ_MPY_CYCLES in all (12: TI's IQNrsmpy benchmark, 20 cycles with
  LCR/LRETR of 4 each), a saturating sum FIX_SAT_CYCLES, any other block its instructions + 3
  (a C28x branch, call or return takes 4 against the M0's 1);
- every listing in docs/c28x-sample.md sums to its stated total, and those totals, the weights'
  charge for each function's M0 path and the sums are the ones in pil_profile.HAND_SAMPLE and the
  appendix's summary table;
- the second estimate pil_profile prints is the weighted one times the sample's ratio.

  test_pil_profile.py ROOT
"""
import os
import re
import sys

ROOT = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "..")
sys.path.insert(0, os.path.join(ROOT, "tools", "pil"))
import pil_profile as pp  # noqa: E402

failures = []


def check(cond, what):
    if not cond:
        failures.append(what)


# Weights (docs/f2812.md, "C28x cycle estimate"): the LCR + LRETR pair of the IQmath benchmarks is
# 8, IQNrsmpy (the same rounding and saturation as iq_mpy) 20 with it.
check(pp.block_cycles("__muldi3", 30, True) == 4 and pp.block_cycles("__muldi3", 11, False) == 0,
      "a 64-bit product helper call is charged 4 cycles, once")
iq_call = pp.block_cycles("iq_mpy", 14, True) + pp.block_cycles("iq_mpy", 5, False) \
    + pp.block_cycles("__aeabi_lmul", 40, True)
check(iq_call == 20 - 8, "an iq_mpy call with its product is charged IQNrsmpy's 20 cycles less LCR/LRETR: %d" % iq_call)
check(pp.block_cycles("fix_add32", 7, True) + pp.block_cycles("fix_add32", 1, False) == 4,
      "a saturating sum is charged 4 cycles")
check(pp.block_cycles("dtc_step", 10, True) == 13 and pp.block_cycles("dtc_step", 1, False) == 4,
      "another block is charged its instructions and 3 for its branch, call or return (4 on the C28x)")

# Flash wait states (--ram-cmd): a function the .cmd does not name pays 5 per instruction, one it
# names none, and gcc's clones (NAME.isra.N) are the .cmd's NAME, as budget.sh counts them.
ram = {"hyst2_sq_bounds", "dtc_step"}
check(pp.flash_wait("dtc_reset", 10, ram) == 50, "a function not in the .cmd pays 5 wait cycles per instruction")
check(pp.flash_wait("dtc_step", 10, ram) == 0 and pp.flash_wait("hyst2_sq_bounds.isra.0", 10, ram) == 0,
      "a function the .cmd names, or a clone of one, runs from RAM")
check(pp.flash_wait("dtc_step.constprop.0", 10, {"dtc"}) == 50, "a clone of a function not named runs from flash")

# The appendix: each listing's rows sum to its total; the totals are HAND_SAMPLE's.
with open(os.path.join(ROOT, "docs", "c28x-sample.md")) as f:
    doc = f.read()
sections = re.split(r"^## ", doc, flags=re.M)
totals = {}
for sec in sections[1:]:
    m = re.match(r"`(\w+)`", sec)
    if not m:
        continue
    rows = re.findall(r"^\| `[^`]+` \| (\d+) \|", sec, flags=re.M)
    total = re.search(r"^\| \*\*total\*\* \| \*\*(\d+)\*\* \|", sec, flags=re.M)
    check(total is not None and rows, "listing of %s has rows and a total" % m.group(1))
    if total is not None:
        check(sum(int(r) for r in rows) == int(total.group(1)),
              "listing of %s sums to %d, stated %s" % (m.group(1), sum(int(r) for r in rows), total.group(1)))
        totals[m.group(1)] = int(total.group(1))
summary = {m.group(1): [int(x) for x in m.group(2, 3, 4, 5)] for m in re.finditer(
    r"^\| `(\w+)` \| [^|]+ \| (\d+) \| (\d+) \| (\d+) \| (\d+) \|$", doc, flags=re.M)}
for name, instr, blocks, products, iqm, sats, hand, hand_ovm in pp.HAND_SAMPLE:
    weighted = pp.weighted_cycles(instr, blocks, products, iqm, sats)
    check(totals.get(name) == hand, "%s: HAND_SAMPLE %d, listing %s" % (name, hand, totals.get(name)))
    row = summary.get(name)
    check(row is not None and row[1] == round(weighted) and row[2] == hand and row[3] == hand_ovm,
          "%s: summary row %s against weights %g, hand %d / %d" % (name, row, weighted, hand, hand_ovm))
weighted_sum = sum(pp.weighted_cycles(*r[1:6]) for r in pp.HAND_SAMPLE)
sums = re.search(r"^\| \*\*sum\*\* \| \| \*\*(\d+)\*\* \| \*\*(\d+)\*\* \| \*\*(\d+)\*\* \| \*\*(\d+)\*\* \|", doc, flags=re.M)
check(sums is not None and int(sums.group(2)) == round(weighted_sum)
      and int(sums.group(3)) == sum(r[6] for r in pp.HAND_SAMPLE)
      and int(sums.group(4)) == sum(r[7] for r in pp.HAND_SAMPLE), "the summary's sums")

# The ratios and the second estimate.
r_c, r_ovm = pp.hand_ratios()
check(abs(r_c - sum(r[6] for r in pp.HAND_SAMPLE) / weighted_sum) < 1e-12, "ratio as written")
check(r_ovm < r_c, "the sums under OVM take fewer cycles than as written")
ratio_text = re.search(r"hand / weights = (\d\.\d\d) for the C as written and (\d\.\d\d)", doc)
check(ratio_text is not None and float(ratio_text.group(1)) == round(r_c, 2)
      and float(ratio_text.group(2)) == round(r_ovm, 2), "the appendix states the ratios pil_profile uses")

if failures:
    for f in failures:
        print("FAIL:", f)
    sys.exit(1)
print("pil_profile weights and hand sample: ratio %.2f as written, %.2f with the sums under OVM" % (r_c, r_ovm))
