#!/usr/bin/python3
"""stack_budget.py - the F2812 image's stack need (C28x ESTIMATE) against M0, where the linker
command files put the stack (linker/f2812_flash*.cmd: .stack > RAMM0, --stack_size=0x400).

usage: stack_budget.py PROJECT_ROOT [--im] [CM0_BUILD_DIR]     (after: cmake --build --preset cross-cm0)

Method. The image's firmware objects (the archive members a relocatable link of its
f2812_main object pulls in, as budget.sh finds them: the application, protocol, operation layer,
laws, fixed-point core, configuration, HAL) are compiled again for cortex-m0 with the cross-cm0
build's own commands (its compile_commands.json, or `ninja -t compdb`) plus -fcallgraph-info=su;
tools/bench/stack_report.py reads the graphs (each function's frame, direct calls; libgcc
helpers' frames from their disassembly). The worst chains:
  ISR         from f2812_adcint_isr (the ADCINT glue: app_isr and all it calls)
  background  main's frame + the worst of the loop's calls (app_background, app_proto_background:
              a parameter write, the commissioning's apply, a reconfiguration), interruptible by the
              ISR: background + ISR + the interrupt's save
  init        main's whole chain (app_init ...), run before interrupts are enabled: alone
C28x words = Cortex-M0 bytes / 2 (the same types take the same words: 16-bit word, 32-bit values
and registers in two words) + the interrupt's save: 15 words the CPU stacks and about 14 the
compiler's ISR saves. The need is the worst of (background + ISR + save) and init; it must be
<= 85 % of M0's 1,024 words. An ESTIMATE: cl2000's frames differ (confirm with its --call_graph
or the map file); a call through a function pointer is not in gcc's graph (listed if any).
Exit status 1 if the need does not fit, 2 if the build is missing."""
import json
import os
import re
import shlex
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools", "bench"))
import stack_report  # noqa: E402

M0_WORDS = 1024
MARGIN_PCT = 85
ISR_SAVE_WORDS = 15 + 14
ISR_ROOT = "f2812_adcint_isr"
LOOP_CALLS = ("app_background", "app_proto_background")


def main():
    args = sys.argv[1:]
    if not args:
        raise SystemExit(__doc__)
    root = os.path.abspath(args[0])
    im = "--im" in args[1:]
    rest = [a for a in args[1:] if a != "--im"]
    cm0 = os.path.abspath(rest[0]) if rest else os.path.join(root, "build", "cross-cm0")
    app, proto, main_t = ("dtc_app", "dtc_proto", "f2812_main")
    if im and os.path.exists(os.path.join(cm0, "firmware", "libdtc_app_im.a")):
        app, proto, main_t = ("dtc_app_im", "dtc_proto_im", "f2812_main_im")
    main_obj = os.path.join(cm0, "target", "f2812", "CMakeFiles", main_t + ".dir", "f2812_main.c.obj")
    archives = ["hal/f2812/libhal_f2812.a"] + ["firmware/lib%s.a" % a for a in (
        app, app + "_init", app + "_flash", "dtc_init", "dtc_im", "dtc_firmware", "dtc_config", "dtc_fixmath", proto,
        "dtc_comm")]
    archives = [os.path.join(cm0, a) for a in archives]
    for f in [main_obj] + archives:
        if not os.path.exists(f):
            print("stack_budget: %s not found (build the cross-cm0 preset first)" % f, file=sys.stderr)
            sys.exit(2)
    # the members the image links: (target, member object name)
    mp = subprocess.run(["arm-none-eabi-ld", "-r", "-M", "-o", os.devnull, main_obj, "--start-group"]
                        + archives + ["--end-group"], capture_output=True, text=True).stdout
    linked = set(re.findall(r"lib([A-Za-z0-9_]+)\.a\(([A-Za-z0-9_.]+)\)", mp))
    linked.add((main_t, "f2812_main.c.obj"))
    ccj = os.path.join(cm0, "compile_commands.json")
    if os.path.exists(ccj):
        db = json.load(open(ccj))
    else:
        db = json.loads(subprocess.run(["ninja", "-C", cm0, "-t", "compdb"], capture_output=True,
                                       text=True, check=True).stdout)
    tmp = tempfile.mkdtemp(prefix="stack_budget.")
    n = 0
    for e in db:
        cmd = shlex.split(e["command"]) if "command" in e else list(e["arguments"])
        if "-o" not in cmd:
            continue
        out = cmd[cmd.index("-o") + 1]
        m = re.search(r"CMakeFiles/([A-Za-z0-9_]+)\.dir/(?:.*/)?([^/]+)$", out)
        if not m or (m.group(1), m.group(2)) not in linked:
            continue
        n += 1
        o = os.path.join(tmp, "%s.%s" % (m.group(1), m.group(2)))
        cmd[cmd.index("-o") + 1] = o
        cmd = [c for c in cmd if c != "-Werror"] + ["-fcallgraph-info=su"]
        subprocess.run(cmd, cwd=e["directory"], check=True, capture_output=True)
    if n < len(linked):
        print("stack_budget: %d of the %d linked objects have a compile command" % (n, len(linked)),
              file=sys.stderr)
        sys.exit(2)
    libgcc = subprocess.run(["arm-none-eabi-gcc", "-mcpu=cortex-m0", "-mthumb", "-print-libgcc-file-name"],
                            capture_output=True, text=True).stdout.strip()
    g = stack_report.Graph(tmp, libgcc)
    isr, isr_path = g.worst_named(ISR_ROOT)
    loop = [(g.worst_named(c), c) for c in LOOP_CALLS]
    (bg, bg_path), _ = max(loop)
    main_frame = g.frame_of(g.title("main"))
    bg += main_frame
    # init: main's calls before the loop (interrupts off), one at a time
    init, init_path = max((g.worst_named(c) for c in g.callees("main") if c not in LOOP_CALLS),
                          default=(0, []))
    init, init_path = init + main_frame, [g.title("main")] + init_path
    image = "IM" if im else "PM"
    print("== stack of the F2812 %s image (%d objects of %s recompiled for cortex-m0 with "
          "-fcallgraph-info=su; C28x ESTIMATE)" % (image, n, os.path.relpath(cm0, root)))

    def show(label, total, path):
        print("  %-11s %5d bytes: %s" % (label, total, " -> ".join(
            "%s %d" % (f.split(":")[-1], g.frame_of(f)) for f in path)))
    show("ISR", isr, isr_path)
    show("background", bg, [g.title("main")] + bg_path)
    show("init", init, init_path)
    need_bg = (bg + isr + 1) // 2 + ISR_SAVE_WORDS
    need_init = (init + 1) // 2
    need = max(need_bg, need_init)
    print("  C28x words: background + ISR + save = %d + %d + %d = %d; init %d (interrupts off)"
          % ((bg + 1) // 2, (isr + 1) // 2, ISR_SAVE_WORDS, need_bg, need_init))
    print("  stack need %d words of M0's %d (%d %%; limit %d %%)"
          % (need, M0_WORDS, 100 * need // M0_WORDS, MARGIN_PCT))
    if g.indirect:
        print("  note: calls through pointers, not followed: %s" % " ".join(sorted(g.indirect)))
    if g.unknown():
        print("  note: frames not found for %s (counted as 0)" % " ".join(g.unknown()))
    subprocess.run(["rm", "-rf", tmp])
    if need * 100 > M0_WORDS * MARGIN_PCT:
        print("stack_budget: the %s image's stack (estimate) does NOT fit %d %% of M0" % (image, MARGIN_PCT),
              file=sys.stderr)
        sys.exit(1)
    print("stack_budget: the %s image's stack fits M0 with a %d %% margin (estimate; confirm with "
          "cl2000's --call_graph, docs/f2812.md)" % (image, 100 - MARGIN_PCT))


if __name__ == "__main__":
    main()
