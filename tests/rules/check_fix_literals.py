#!/usr/bin/env python3
"""Fixed-point literals that come out the same on every target.

Q15(x), Q31(x) and IQ(x) (firmware/fixmath/fixmath.h) are folded by the compiler in its `double`,
which is 64 bits on the host and arm-none-eabi but 32 bits on the C28x COFF ABI and on avr-gcc.
A literal that needs more than float's 24 significant bits (Q31(1/sqrt(3)), IQ(1/3), IQ(0.4))
therefore gives the DSP another constant than the SIL build, and the same firmware computes
1-LSB different results on the board than in the tests (the processor-in-the-loop AVR replay
shows it as a difference in the trace). This check evaluates every such literal in the firmware
as both compilers do, in 64-bit and in 32-bit floating point, and fails on each one whose two
values differ: write it as an integer (fixmath.h FIX_Q31_*, or a ratio of integers with IQ_FRAC /
Q31_FRAC) instead.

An argument must be a constant expression of numbers, + - * / and parentheses, and object-like
macros of the same file or fixmath.h with such values; one that cannot be evaluated is reported
too (the macro's contract).

Usage: check_fix_literals.py DIR...   (exit 1 on any finding; prints file:line: literal and values)
"""
import ast
import os
import re
import struct
import sys

SCALE = {"Q15": (32768.0, 32767.5 / 32768.0, -1.0, 32767, -32768),
         "Q31": (2147483648.0, 2147483647.5 / 2147483648.0, -1.0, 2147483647, -2147483648),
         "IQ": (16777216.0, 2147483647.5 / 16777216.0, -128.0, 2147483647, -2147483648)}
CALL = re.compile(r"(?<![A-Za-z0-9_])(Q15|Q31|IQ)\(")
DEFINE = re.compile(r"^\s*#\s*define\s+([A-Za-z_][A-Za-z0-9_]*)\s+(.+?)\s*(?:/\*.*)?$", re.M)


def f32(x):
    return struct.unpack("<f", struct.pack("<f", x))[0]


def evaluate(node, narrow, names):
    """The value of a constant expression, each operation rounded to float32 when narrow."""
    r = f32 if narrow else float
    if isinstance(node, ast.Expression):
        return evaluate(node.body, narrow, names)
    if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)):
        return r(float(node.value))
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
        v = evaluate(node.operand, narrow, names)
        return -v if isinstance(node.op, ast.USub) else v
    if isinstance(node, ast.BinOp) and isinstance(node.op, (ast.Add, ast.Sub, ast.Mult, ast.Div)):
        a = evaluate(node.left, narrow, names)
        b = evaluate(node.right, narrow, names)
        op = node.op
        v = a + b if isinstance(op, ast.Add) else a - b if isinstance(op, ast.Sub) else \
            a * b if isinstance(op, ast.Mult) else a / b
        return r(v)
    if isinstance(node, ast.Name) and node.id in names:
        return evaluate(ast.parse(names[node.id], mode="eval"), narrow, names)
    raise ValueError("not a constant expression")


def fixed(kind, x, narrow):
    """The macro of fixmath.h on x, its double being float32 when narrow."""
    r = f32 if narrow else float
    scale, hi, lo, vmax, vmin = SCALE[kind]
    if x >= r(hi):
        return vmax
    if x <= lo:
        return vmin
    v = r(r(x * r(scale)) + (0.5 if x >= 0 else -0.5))
    return int(v)  # C's conversion truncates towards zero


def c_to_py(text):
    text = re.sub(r"\b(\d+\.?\d*(?:[eE][-+]?\d+)?)[uUlLfF]+\b", r"\1", text)
    text = re.sub(r"\(\s*(?:double|float|int32_t|int64_t|iq_t|q31_t|q15_t)\s*\)", "", text)
    return text.strip()


def argument(src, start):
    depth = 1
    i = start
    while i < len(src) and depth:
        depth += {"(": 1, ")": -1}.get(src[i], 0)
        i += 1
    return src[start:i - 1]


def check_file(path, common):
    src = open(path, encoding="utf-8", errors="replace").read()
    names = dict(common)
    for m in DEFINE.finditer(src):
        names[m.group(1)] = c_to_py(m.group(2))
    found = []
    for m in CALL.finditer(src):
        line_start = src.rfind("\n", 0, m.start()) + 1
        line = src[line_start:src.find("\n", m.start())]
        if re.match(r"\s*#\s*define\s+(Q15|Q31|IQ)\(", line) or line.lstrip().startswith(("*", "/*", "//")):
            continue
        arg = argument(src, m.end())
        if arg.strip() == "x":  # a macro's own parameter (fixmath.h's definitions)
            continue
        lineno = src.count("\n", 0, m.start()) + 1
        try:
            tree = ast.parse(c_to_py(arg), mode="eval")
            wide = fixed(m.group(1), evaluate(tree, False, names), False)
            narrow = fixed(m.group(1), evaluate(tree, True, names), True)
        except (ValueError, SyntaxError, RecursionError, ZeroDivisionError) as e:
            found.append("%s:%d: %s(%s): cannot evaluate (%s)" % (path, lineno, m.group(1), arg, e))
            continue
        if wide != narrow:
            found.append("%s:%d: %s(%s) is %d with a 64-bit double, %d with a 32-bit one (C28x, AVR)"
                         % (path, lineno, m.group(1), arg, wide, narrow))
    return found


def main(argv):
    if len(argv) < 2:
        sys.stderr.write(__doc__)
        return 2
    common = {}
    for d in argv[1:]:
        fm = os.path.join(d, "fixmath", "fixmath.h")
        if os.path.exists(fm):
            for m in DEFINE.finditer(open(fm).read()):
                common[m.group(1)] = c_to_py(m.group(2))
    found = []
    count = 0
    for d in argv[1:]:
        for root, _, files in os.walk(d):
            for f in sorted(files):
                if f.endswith((".c", ".h", ".inc")):
                    count += 1
                    found += check_file(os.path.join(root, f), common)
    for line in found:
        print(line)
    print("check_fix_literals: %d files, %d literals that differ between a 64- and a 32-bit double"
          % (count, len(found)))
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
