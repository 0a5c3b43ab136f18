#!/usr/bin/env python3
"""Seeds of fuzz_scenario (fuzz_scenario.cpp): every shipped scenario as a TOML input (first byte 0),
one with --set overrides (first byte 1) and a few sweep command lines (first byte 2).

    scenario_seeds.py SOURCE_DIR CORPUS_DIR
"""
import pathlib
import sys


def main(src, corpus):
    out = pathlib.Path(corpus)
    out.mkdir(parents=True, exist_ok=True)
    for old in out.glob("seed-*"):
        old.unlink()
    n = 0
    for toml in sorted(pathlib.Path(src, "tools", "scenarios").glob("*.toml")):
        (out / f"seed-{n:03d}").write_bytes(b"\x00" + toml.read_bytes())
        n += 1
    (out / f"seed-{n:03d}").write_bytes(b"\x01duration_s = 0.1\n[motor]\nrs_ohm = 0.6\n\n"
                                        b"metrics_window_s=0.05\ncontrol.speed_ref_rpm=300\n")
    n += 1
    (out / f"seed-{n:03d}").write_bytes(b"\x02\x00motor.rs_ohm=0.5,0.6\n\x01duration_s=0.1,0.2\n"
                                        b"\x02load.torque_nm=normal:0.3:0.01\n\x03imbalance_pct<8\n"
                                        b"\x03fundamental_a[A]>0\n")
    n += 1
    print(f"{n} seeds in {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:3]))
