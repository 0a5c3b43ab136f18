#!/usr/bin/env python3
"""Seeds of fuzz_sil_cli (fuzz_sil_cli.cpp): one command line of each dtc-sil command with every
option it takes, the arguments separated by '\\n', for the fuzzer to mutate.

    sil_cli_seeds.py CORPUS_DIR
"""
import pathlib
import sys

SEEDS = [
    ["run", "s.toml", "--out", "d", "--set", "duration_s=0.1", "--overlay", "o.toml", "--decimate", "10",
     "--no-trace", "--quiet", "--force", "--record-isr", "r.bin"],
    ["check", "s.toml", "--set", "a=1", "--overlay", "o.toml"],
    ["identify", "s.toml", "--out", "d", "--set", "a=1", "--overlay", "o.toml", "--max-time", "10"],
    ["serve", "s.toml", "--serial", "/tmp/l", "--pace", "1", "--duration-s", "2", "--out", "d", "--set", "a=1",
     "--decimate", "2", "-q"],
    ["keys"],
    ["sweep", "s.toml", "--out", "d", "--set", "a=1", "--overlay", "o.toml", "--grid", "k=1,2", "--zip", "z=1,2",
     "--sample", "m=normal:1:0.1", "--n", "3", "--seed", "7", "--jobs", "2", "--timeout-s", "60", "--resume",
     "--shard", "0/2", "--assert", "imbalance_pct<8", "--dask", "tcp://h:8786", "--chunk", "5", "--quiet",
     "--allow-failed-runs", "--keep-runs"],
    ["sweep-merge", "--out", "d", "a", "b"],
    ["sweep-exec", "--jobs", "2"],
    ["run", "--help"],
]


def main(corpus):
    out = pathlib.Path(corpus)
    out.mkdir(parents=True, exist_ok=True)
    for old in out.glob("seed-*"):
        old.unlink()
    for n, args in enumerate(SEEDS):
        (out / f"seed-{n:02d}").write_bytes("\n".join(args).encode())
    print(f"{len(SEEDS)} seeds in {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
