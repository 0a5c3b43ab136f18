#!/usr/bin/python3
"""Index from every numbered equation, table and figure of the two papers to the code that cites it.

The papers (/work/shared/papers/, index README.md there) are the project's specification:
  Casadei  D. Casadei, G. Serra, A. Tani, L. Zarri, "Assessment of direct torque control for
           induction motor drives", Bull. Pol. Ac.: Tech. 54(3), 2006: eqs. 1-34 and A1-A11,
           Tables 1-5, Figs. 1-36 and A1-A2.
  Hoang    K. D. Hoang, Z. Q. Zhu, M. P. Foster, "Influence and compensation of inverter voltage drop
           in direct torque-controlled four-switch three-phase PM brushless AC drives", IEEE Trans.
           Power Electron. 26(8), 2011: eqs. 1-40, Tables I-X, Figs. 1-20.
Both number their equations from 1, so code cites an equation with its paper: "Casadei eq. 20",
"Hoang eqs. 15-16", "Hoang Table VI", "Casadei Fig. 17b". This script scans the source tree
(firmware, hal, model, target, tools, tests) for those citations and writes a markdown index: for
every item of both papers, the files and functions that cite it outside tests/ (the implementation,
the nearest enclosing or following C/C++ function or Python def, best effort) and the files under
tests/ that cite it (the checks). An item nothing cites shows the reason of NOT_CITED below.

A citation is a paper name ("Casadei", "Hoang", optionally "'s", "et al.", the year) followed by a
kind (eq./eqs./equation(s), Table(s), Fig(s)./Figure(s)) and a list of numbers: "20", "(20)",
"20-22", "(1)-(5)", "8-9", "29 and 31", "18, 23, 24", "IX/X", "V-VI", "A1-A11", "17b", "9(b)".
Further kinds joined to it by "+", "/", ",", "and", "with" or an opening parenthesis belong to the
same paper ("Hoang Table III + eq. 20", "Hoang Table VI (eqs. 37-38)").

    /usr/bin/python3 tools/docs/paper_index.py            # print the section
    /usr/bin/python3 tools/docs/paper_index.py --write    # replace it in docs/firmware-core.md
    /usr/bin/python3 tools/docs/paper_index.py --check    # exit 1 if the doc's section is stale
    /usr/bin/python3 tools/docs/paper_index.py --bare     # list citations that do not name the paper

The section sits between <!-- paper-index:begin --> and <!-- paper-index:end --> in
docs/firmware-core.md. Run --write after changing a citation; ctest rules.paper_index runs --check.
"""
import argparse
import os
import re
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
DOC = os.path.join("docs", "firmware-core.md")
BEGIN = "<!-- paper-index:begin -->"
END = "<!-- paper-index:end -->"
SCAN_DIRS = ["firmware", "hal", "model", "target", "tools", "tests"]
SCAN_EXT = (".c", ".h", ".cpp", ".hpp", ".py", ".sh", ".toml", ".cmake", ".ld", ".txt")
SELF = os.path.join("tools", "docs", "paper_index.py")

ROMAN = ["I", "II", "III", "IV", "V", "VI", "VII", "VIII", "IX", "X"]

# Every numbered item of each paper, in the paper's order.
ITEMS = {
    "Casadei": ([("eq", str(n)) for n in range(1, 35)] + [("eq", "A%d" % n) for n in range(1, 12)]
                + [("Table", str(n)) for n in range(1, 6)]
                + [("Fig", str(n)) for n in range(1, 37)] + [("Fig", "A1"), ("Fig", "A2")]),
    "Hoang": ([("eq", str(n)) for n in range(1, 41)] + [("Table", r) for r in ROMAN]
              + [("Fig", str(n)) for n in range(1, 21)]),
}

# Why an item no code cites has no implementation: "not applicable" (nothing to implement: a
# diagram, a derivation step, a photograph, a measurement of the authors' rig) or "not implemented"
# (could be, and is not).
NOT_CITED = {
    "Casadei": {
        ("eq", "3"): ("not applicable", "eq. 1 without the resistive drop, an argument of the text"),
        ("eq", "4"): ("not applicable", "discrete flux step of the argument in sec. 2"),
        ("eq", "5"): ("not applicable", "length of the flux step, an argument of the text"),
        ("eq", "6"): ("not applicable", "rotor flux against stator flux in the rotor frame; the plant integrates A7-A9"),
        ("eq", "7"): ("not applicable", "Laplace form of eq. 6, an argument of the text"),
        ("eq", "8"): ("not applicable", "torque from the flux magnitudes and angle; the code uses A10"),
        ("eq", "10"): ("not applicable", "discrete-time step of eq. 9, a step of the derivation of eqs. 13-15"),
        ("eq", "11"): ("not applicable", "discrete-time step of eq. 9, a step of the derivation of eqs. 13-15"),
        ("eq", "12"): ("not applicable", "torque at t_k+1, a step of the derivation of eqs. 13-15"),
        ("eq", "25"): ("not applicable", "definition of the mismatches used in eqs. 26-28"),
        ("eq", "A2"): ("not applicable", "zero-sequence component; the machine is star-connected without neutral"),
        ("eq", "A3"): ("not applicable", "inverse transform; the code projects alpha-beta onto the phases directly"),
        ("eq", "A4"): ("not applicable", "inverse transform; the code projects alpha-beta onto the phases directly"),
        ("eq", "A5"): ("not applicable", "inverse transform; the code projects alpha-beta onto the phases directly"),
        ("eq", "A11"): ("not applicable", "torque from the two fluxes; the code uses A10"),
        ("Table", "2"): ("not applicable", "qualitative effect of each vector, the reasoning behind Table 3"),
        ("Table", "4"): ("not applicable", "simulation settings of sec. 13; used as the IM rig's periods"),
        ("Fig", "1"): ("not implemented", "flux trajectories for two cycle periods; no test compares them"),
        ("Fig", "2"): ("not applicable", "diagram of the flux hysteresis band"),
        ("Fig", "3"): ("not applicable", "diagram of the stator and rotor flux vectors"),
        ("Fig", "4"): ("not applicable", "block diagram of basic DTC"),
        ("Fig", "8"): ("not applicable", "diagram of the torque variation of eq. 15"),
        ("Fig", "11"): ("not applicable", "block diagram of DSC"),
        ("Fig", "12"): ("not applicable", "DSC principle diagram (its caption is missing from the text)"),
        ("Fig", "16"): ("not applicable", "block diagram of the improved estimator"),
        ("Fig", "18"): ("not applicable", "block diagram of SFVC"),
        ("Fig", "26"): ("not applicable", "diagram of the 19 DSVM vectors"),
        ("Fig", "27"): ("not applicable", "diagram of the DSVM speed ranges"),
        ("Fig", "28"): ("not applicable", "diagram of the high-speed DSVM vectors"),
        ("Fig", "A1"): ("not applicable", "inverter schematic"),
        ("Fig", "A2"): ("not applicable", "diagram of the inverter voltage vectors"),
    },
    "Hoang": {
        ("eq", "6"): ("not applicable", "voltage equation; the plant integrates the per-phase circuit"),
        ("eq", "7"): ("not applicable", "voltage equation; the plant integrates the per-phase circuit"),
        ("eq", "12"): ("not applicable", "flux angle; the firmware finds the sector without an arctangent"),
        ("eq", "21"): ("not applicable", "phase equations with R_on, a step of the derivation of eqs. 24-27"),
        ("eq", "22"): ("not applicable", "phase equations with R_on, a step of the derivation of eqs. 24-27"),
        ("eq", "23"): ("not applicable", "phase equations with R_on, a step of the derivation of eqs. 24-27"),
        ("eq", "24"): ("not applicable", "SSTP flux with R_on, an argument of the text"),
        ("eq", "25"): ("not applicable", "SSTP flux with R_on, an argument of the text"),
        ("eq", "27"): ("not applicable", "FSTP beta flux with R_on, carried into eq. 38"),
        ("eq", "28"): ("not applicable", "phase equations with v_f, a step of the derivation of eqs. 31-34"),
        ("eq", "29"): ("not applicable", "phase equations with v_f, a step of the derivation of eqs. 31-34"),
        ("eq", "30"): ("not applicable", "phase equations with v_f, a step of the derivation of eqs. 31-34"),
        ("eq", "32"): ("not applicable", "beta flux with v_f, carried into eq. 38"),
        ("Fig", "2"): ("not applicable", "diagram of the voltage vectors"),
        ("Fig", "4"): ("not applicable", "block diagram of the drive"),
        ("Fig", "10"): ("not applicable", "IPM case temperatures of the authors' rig; the plant has no thermal model"),
    },
}

NUM = r"\(?A?\d+\)?[a-z]?(?:\([a-z]\))?"
ROM = r"\(?(?:VIII|VII|VI|IV|IX|III|II|I|V|X)\)?(?![A-Za-z0-9_])"
ITEM = r"(?:%s|%s)" % (NUM, ROM)
LIST = r"%s(?:\s*(?:-|–|/|,|and|to|or)\s*%s)*" % (ITEM, ITEM)
KIND = r"(?:[Ee]qs?\.|[Ee]quations?|Tables?|Figs?\.|Figures?)"
PAPER = r"\b(Casadei|Hoang)(?:'s)?(?:\s+et\s+al\.?)?(?:,?\s+(?:2006|2011))?,?\s+"
SECTION = r"(?:secs?\.\s*[\w.\-]+,?\s*)?"  # "Casadei sec. 13, Table 5"
FIRST = re.compile(PAPER + SECTION + r"(%s)\s*(%s)" % (KIND, LIST))
MORE = re.compile(r"\s*(?:\+|/|,|;|and|with|then|\()?\s*(?:the\s+)?(%s)\s*(%s)" % (KIND, LIST))


def kind_of(word):
    w = word.lower()
    if w.startswith("eq"):
        return "eq"
    if w.startswith("table"):
        return "Table"
    return "Fig"


def expand(paper, kind, text):
    """'20-22' -> ['20', '21', '22'], 'IX/X' -> ['IX', 'X'], 'A1-A11' -> A1..A11, '17b' -> ['17']."""
    toks = re.findall(r"A?\d+|VIII|VII|VI|IV|IX|III|II|I|V|X|-|–|to", text)
    out, prev, rng = [], None, False
    for t in toks:
        if t in ("-", "–", "to"):
            rng = prev is not None
            continue
        if rng and prev is not None:
            a, b = prev, t
            if a.isdigit() and b.isdigit():
                out += [str(n) for n in range(int(a) + 1, int(b) + 1)]
            elif a.startswith("A") and b.startswith("A"):
                out += ["A%d" % n for n in range(int(a[1:]) + 1, int(b[1:]) + 1)]
            elif a in ROMAN and b in ROMAN:
                out += ROMAN[ROMAN.index(a) + 1:ROMAN.index(b) + 1]
            else:
                out.append(b)
            rng = False
        else:
            out.append(t)
        prev = t
    valid = {i for k, i in ITEMS[paper] if k == kind}
    return [i for i in out if i in valid]


def citations(line):
    """[(paper, kind, item)] cited on one line."""
    found = []
    for m in FIRST.finditer(line):
        paper = m.group(1)
        found += [(paper, kind_of(m.group(2)), i) for i in expand(paper, kind_of(m.group(2)), m.group(3))]
        pos = m.end()
        while True:
            n = MORE.match(line, pos)
            if not n:
                break
            found += [(paper, kind_of(n.group(1)), i) for i in expand(paper, kind_of(n.group(1)), n.group(2))]
            pos = n.end()
    return found


C_KEYWORDS = {"if", "for", "while", "switch", "return", "sizeof", "defined", "do", "else", "case",
              "static_assert", "_Static_assert"}
C_DEF = re.compile(r"^(?:[A-Za-z_][\w:<>,\*&\s]*?[\s\*&:])?([A-Za-z_][\w:~]*)\s*\(")
ATTR = re.compile(r"__attribute__\s*\(\(.*?\)\)\s*|\b[A-Z][A-Z0-9_]*_RAMFUNC\b\s*")
GTEST = re.compile(r"^(?:TEST|TEST_F|TEST_P)\s*\(\s*(\w+)\s*,\s*(\w+)\s*\)")
NAMESPACE = re.compile(r"^\s*(?:namespace\b[^{]*|extern\s*)\{")
PY_DEF = re.compile(r"^(\s*)(?:async\s+)?(?:def|class)\s+(\w+)")


def c_functions(lines):
    """Per line: the name of the function whose body holds it, or of the next top-level declaration
    (a comment above a function or a prototype describes it), or ''."""
    braces, names, defs = [], [None] * len(lines), []
    in_comment, cur = False, None
    for i, raw in enumerate(lines):
        s = raw
        # Strip comments and strings to count braces.
        out, j = [], 0
        while j < len(s):
            if in_comment:
                k = s.find("*/", j)
                if k < 0:
                    j = len(s)
                else:
                    in_comment, j = False, k + 2
                continue
            if s.startswith("/*", j):
                in_comment, j = True, j + 2
            elif s.startswith("//", j):
                break
            elif s[j] in "\"'":
                q, j = s[j], j + 1
                while j < len(s) and s[j] != q:
                    j += 2 if s[j] == "\\" else 1
                j += 1
            else:
                out.append(s[j])
                j += 1
        code = ATTR.sub("", "".join(out))
        depth = sum(1 for b in braces if b)
        if depth == 0 and code.strip() and not code.startswith((" ", "\t", "#", "}", "{")):
            g = GTEST.match(code)
            m = C_DEF.match(code)
            if g:
                defs.append((i, "%s.%s" % g.groups()))
                cur = defs[-1][1]
            elif m and m.group(1) not in C_KEYWORDS and "=" not in code.split("(")[0]:
                defs.append((i, m.group(1)))
                cur = m.group(1)
            elif "{" in code or ";" in code:
                cur = None  # a type, a variable or a prototype: outside any function body
        names[i] = (depth, cur)
        # Namespace and extern "C" braces do not open a body: what they hold is at top level.
        scope = bool(NAMESPACE.match(code))
        for ch in code:
            if ch == "{":
                braces.append(not scope)
                scope = False
            elif ch == "}" and braces:
                braces.pop()
    result = []
    for i in range(len(lines)):
        d, cur = names[i]
        if d > 0 and cur:
            result.append(cur)
            continue
        result.append(attached(lines, i, dict(defs)))
    return result


def attached(lines, i, defs, comment=("//", "/*", "*", "#")):
    """The definition a comment at line i documents: the one starting on the first line after the
    comment block, with no blank line in between (else '')."""
    j = i
    while j < len(lines) and j not in defs:
        t = lines[j].strip()
        if not t or (j > i and not t.startswith(comment) and not lines[j - 1].rstrip().endswith("\\")):
            return ""
        j += 1
    return defs.get(j, "")


def py_functions(lines):
    result, stack = [], []
    defs = [(i, len(m.group(1)), m.group(2)) for i, l in enumerate(lines) for m in [PY_DEF.match(l)] if m]
    for i, l in enumerate(lines):
        ind = len(l) - len(l.lstrip()) if l.strip() else None
        while stack and ind is not None and ind <= stack[-1][1] and stack[-1][0] != i:
            stack.pop()
        for d in defs:
            if d[0] == i:
                stack.append(d)
        if stack and stack[-1][0] != i:
            result.append(stack[-1][2])
        else:
            result.append(attached(lines, i, {l2: n for (l2, _, n) in defs}))
    return result


def source_files(root):
    """(path relative to root, file name, lines) of every scanned source file, in a fixed order."""
    for top in SCAN_DIRS:
        for dirpath, dirnames, filenames in os.walk(os.path.join(root, top)):
            dirnames[:] = sorted(d for d in dirnames if not d.startswith((".", "__pycache__")))
            for fn in sorted(filenames):
                if not (fn.endswith(SCAN_EXT) or fn == "CMakeLists.txt"):
                    continue
                path = os.path.join(dirpath, fn)
                rel = os.path.relpath(path, root).replace(os.sep, "/")
                if rel == SELF.replace(os.sep, "/"):
                    continue
                try:
                    with open(path, encoding="utf-8") as f:
                        yield rel, fn, f.read().split("\n")
                except (UnicodeDecodeError, OSError):
                    continue


def scan(root):
    """{(paper, kind, item): {"impl": set of 'file:function', "test": set of files}}"""
    index = {}
    for rel, fn, lines in source_files(root):
        hits = [(i, c) for i, l in enumerate(lines) for c in citations(l)]
        if not hits:
            continue
        if fn.endswith(".py"):
            funcs = py_functions(lines)
        elif fn.endswith((".c", ".h", ".cpp", ".hpp")):
            funcs = c_functions(lines)
        else:
            funcs = [""] * len(lines)
        test = rel.startswith("tests/")
        for i, c in hits:
            e = index.setdefault(c, {"impl": set(), "test": set()})
            if test:
                e["test"].add(rel)
            else:
                e["impl"].add("%s: %s" % (rel, funcs[i]) if funcs[i] else rel)
    return index


BARE = re.compile(r"(?<![\w.])(%s)\s*(%s)" % (KIND, LIST))
PAPER_NAME = re.compile(r"\b(?:Casadei|Hoang)")


def bare(root):
    """'file:line: text' for every line with an equation, table or figure number and no paper name
    before it on the line (a line continuing a sentence that named the paper is listed too)."""
    out = []
    for rel, fn, lines in source_files(root):
        for i, l in enumerate(lines):
            for m in BARE.finditer(l):
                if not re.search(r"\d|\b[IVX]+\b", m.group(2)) or PAPER_NAME.search(l[:m.start()]):
                    continue
                out.append("%s:%d: %s" % (rel, i + 1, l.strip()))
                break
    return out


def label(paper, kind, item):
    return {"eq": "eq. %s", "Table": "Table %s", "Fig": "Fig. %s"}[kind] % item


def cell(items):
    """'file: function' entries grouped by file: `file` (f, g)."""
    by_file = {}
    for x in items:
        path, _, fn = x.partition(": ")
        by_file.setdefault(path, set())
        if fn:
            by_file[path].add(fn)
    return "<br>".join("`%s`%s" % (p, " (%s)" % ", ".join("`%s`" % f for f in sorted(fs)) if fs else "")
                       for p, fs in sorted(by_file.items()))


def render(index):
    out = [BEGIN, "",
           "Generated by `tools/docs/paper_index.py --write` from the citations in the code "
           "(\"Casadei eq. 20\", \"Hoang Table VI\"); `ctest -R rules.paper_index` fails when this "
           "section is stale. *Implemented in*: files outside `tests/` that cite the item, with the "
           "nearest enclosing or following function; *checked by*: files under `tests/` that cite it. "
           "An item nothing cites carries the reason of the script's `NOT_CITED` table.", ""]
    totals = []
    for paper in ("Casadei", "Hoang"):
        cited = impl = test = 0
        rows = []
        for kind, item in ITEMS[paper]:
            e = index.get((paper, kind, item))
            if e:
                cited += 1
                impl += bool(e["impl"])
                test += bool(e["test"])
                rows.append("| %s | %s | %s |" % (label(paper, kind, item),
                                                   cell(e["impl"]) or "(tests only)", cell(e["test"]) or "none"))
            else:
                status, why = NOT_CITED[paper].get((kind, item), ("not cited", "no citation names the paper (`--bare` lists the citations without one)"))
                rows.append("| %s | %s: %s | |" % (label(paper, kind, item), status, why))
        n = len(ITEMS[paper])
        totals.append("%s: %d of %d items cited (%d in code outside tests/, %d in tests)" % (paper, cited, n, impl, test))
        title = ("Casadei et al. 2006 (induction machine)" if paper == "Casadei"
                 else "Hoang, Zhu, Foster 2011 (PM BLAC, FSTP)")
        out += ["### %s" % title, "", "| item | implemented in | checked by |", "|---|---|---|"] + rows + [""]
    head = out[:4] + ["Coverage: " + "; ".join(totals) + ".", ""]
    out = head + out[6:] + [END]
    return "\n".join(out)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    g = ap.add_mutually_exclusive_group()
    g.add_argument("--write", action="store_true", help="replace the marked section of %s" % DOC)
    g.add_argument("--check", action="store_true", help="exit 1 if the marked section of %s is stale" % DOC)
    g.add_argument("--bare", action="store_true", help="list the citations that do not name their paper")
    ap.add_argument("--root", default=ROOT, help="source tree (default: this checkout)")
    a = ap.parse_args(argv)
    if a.bare:
        print("\n".join(bare(a.root)))
        return 0
    section = render(scan(a.root))
    if not (a.write or a.check):
        print(section)
        return 0
    doc = os.path.join(a.root, DOC)
    with open(doc, encoding="utf-8") as f:
        text = f.read()
    b, e = text.find(BEGIN), text.find(END)
    if b < 0 or e < b:
        print("%s: markers %s ... %s not found" % (DOC, BEGIN, END), file=sys.stderr)
        return 1
    new = text[:b] + section + text[e + len(END):]
    if a.check:
        if new != text:
            print("%s: the paper index is stale; run /usr/bin/python3 tools/docs/paper_index.py --write"
                  % DOC, file=sys.stderr)
            return 1
        return 0
    if new != text:
        with open(doc, "w", encoding="utf-8") as f:
            f.write(new)
    return 0


if __name__ == "__main__":
    sys.exit(main())
