#!/usr/bin/python3
"""ctest sil.papers_report: runs tools/report/papers.py --short and checks DIR/status.json.

    test_papers_report.py DTC_SIL OUT_DIR

Fails when status.json misses a numbered result figure or table of either paper (papers.py's
CASADEI_ITEMS, hoang_items.ITEMS), when an entry's status is not one of the three, when a
"deviates" entry has no reason, or when one of the Hoang figures this project reproduces is no
longer "reproduced" (each one's check, with its margin, is in tools/report/hoang_items.py), or when
Casadei Figs. 35-36 are no longer "reproduced" (tools/report/casadei_items.py), or when a measured
reason of a deviating Hoang item (Fig. 17, Tables IX and X) no longer holds on the runs.
"""
import json
import os
import subprocess
import sys

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "tools", "report"))
import papers  # noqa: E402
from hoang_common import BALANCED_PCT as papers_bal  # noqa: E402

# Hoang figures reproduced on the shipped scenarios, each by the paper's statement with a margin.
# Casadei figures reproduced by this report's checks (each one's margin in tools/report/casadei_items.py).
CASADEI_REPRODUCED = ["Fig. 1", "Fig. 6", "Fig. 7", "Fig. 9", "Fig. 10", "Fig. 19", "Fig. 20", "Fig. 21", "Fig. 22",
                      "Fig. 23", "Fig. 25", "Fig. 31", "Fig. 35", "Fig. 36"]
REPRODUCED = ["Fig. 5 (b)", "Fig. 6 (b)", "Fig. 7 (b)", "Fig. 8 (b)", "Fig. 11", "Fig. 12", "Fig. 13", "Fig. 14",
              "Fig. 15", "Fig. 16"]


def main():
    exe, out = sys.argv[1], sys.argv[2]
    rc = subprocess.run([sys.executable, os.path.join(ROOT, "tools", "report", "papers.py"), "--short", "--out", out,
                         "--exe", exe]).returncode
    with open(os.path.join(out, "status.json")) as f:
        entries = json.load(f)
    problems = papers.check(entries)
    got = {e["item"]: e for e in entries if e["paper"] == "hoang"}
    for item in REPRODUCED:
        e = got.get(item)
        if e is None or e["status"] != "reproduced":
            problems.append("hoang %s: %s (%s)" % (item, e and e["status"], e and e["reason"]))
    cas = {e["item"]: e for e in entries if e["paper"] == "casadei"}
    for item in CASADEI_REPRODUCED:
        e = cas.get(item)
        if e is None or e["status"] != "reproduced":
            problems.append("casadei %s: %s (%s)" % (item, e and e["status"], e and e["reason"]))
    # Hoang Fig. 17 deviates with a measured cause: Table VII's back-EMF under the voltage model. The reason
    # holds while the SIL's light-load imbalance is the ideal law's (tools/report/hoang_emf.py) on the SSTP
    # and on the FSTP, and within 10 % once the back-EMF is balanced.
    f17 = got.get("Fig. 17")
    if f17 and f17["status"] == "deviates":
        light = f17["measured"].get("light-load causes (imbalance %, mean over seeds)", {})
        law = f17["measured"].get("ideal law on Table VII's machine (hoang_emf)", {})
        for ld in ("inertial", "half"):
            ideal = (law.get(ld) or {}).get("imbalance_pct")
            for lab in ("as shipped", "SSTP, compensation [29]"):
                v = light.get("%s, %s" % (ld, lab))
                if ideal is None or v is None or not 0.6 * ideal <= v <= 1.15 * ideal:
                    problems.append("hoang Fig. 17 %s, %s: %s %% not within 0.6..1.15 x the ideal law's %s %%"
                                    % (ld, lab, v, ideal))
            v = light.get("%s, balanced back-EMF" % ld)
            if v is None or v > papers_bal:
                problems.append("hoang Fig. 17 %s, balanced back-EMF: %s %% (> %.0f %%)" % (ld, v, papers_bal))
    # Hoang Table IX's reason names the Table VII back-EMF and the dead time as causes of the bare algorithm's
    # excess: each, removed alone, lowers the simple and the proposed rows by at least 2 points.
    ix = got.get("Table IX")
    rows = (ix or {}).get("measured", {}).get("bare algorithm, imbalance % none / simple / proposed, one change at a time", {})
    vals = {k.split(" ")[0]: v.split(" / ") for k, v in rows.items()}
    try:
        for cause in ("balanced_emf", "dead_time_0"):
            for c in (1, 2):
                if not float(vals[cause][c]) <= float(vals["bare"][c]) - 2.0:
                    problems.append("hoang Table IX: %s does not lower row %d by 2 points (%s against %s)"
                                    % (cause, c, vals[cause][c], vals["bare"][c]))
    except (KeyError, ValueError, IndexError) as e:
        problems.append("hoang Table IX: bare-algorithm rows missing or a run tripped (%s)" % e)
    # Hoang Table X's reason: the uncompensated SSTP's torque over-estimate is the device drops; the paper's
    # 0.3296 N*m lies between the SIL's with ideal devices and with Table IV's drops.
    tx = (got.get("Table X") or {}).get("measured", {}).get("uncompensated predicted torque against the device drops (N*m)", {})
    sstp = tx.get("SSTP", {})
    if not (sstp.get("ideal devices") or 1) < 0.3296 < (sstp.get("Table IV") or 0):
        problems.append("hoang Table X: the paper's SSTP 0.3296 N*m not between the SIL's ideal-device and Table IV "
                        "estimates (%s)" % sstp)
    # Hoang Figs. 5-8 (a) run once dtc-sil has the ITC law (hoang_items.itc_sets()); then they are checked too.
    for item, e in got.items():
        if item.endswith("(a)") and e["measured"] and e["status"] != "reproduced":
            problems.append("hoang %s (ITC): %s (%s)" % (item, e["status"], e["reason"]))
    if not os.path.getsize(os.path.join(out, "index.html")):
        problems.append("index.html empty")
    for p in problems:
        print("FAIL: " + p)
    n = {s: sum(e["status"] == s for e in entries) for s in papers.STATUSES}
    print("status.json: %d entries, %s; papers.py exit %d" % (len(entries), n, rc))
    return 1 if problems or rc != 0 else 0


if __name__ == "__main__":
    sys.exit(main())
