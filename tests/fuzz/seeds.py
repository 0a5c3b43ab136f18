#!/usr/bin/env python3
"""Writes the fuzz slice's seed inputs (docs/fuzzing.md) into a fresh directory.

The fuzzer alone does not reach the issue-16 reconfiguration within the slice: it needs a
six-switch board with relays, a turning encoder and one phase at zero current while the other
two carry current for 60 electrical degrees (app_fault.c app_fault_open_phase). One seed starts there;
the fuzzer mutates it like any other input. Byte layout: tests/fuzz/fuzz_app_core.c
(base_config, fuzz_config_and_init, run_record).

usage: seeds.py DIR
"""
import os
import shutil
import sys


def record(periods, dev, scale=0, enc_vel=None):
    """One measurement record held for `periods` (1..32): ADC deviations (5 int8, times 4^scale)."""
    op = (periods - 1) << 3
    mb = scale & 3
    out = [op]
    extra = []
    if enc_vel is not None:
        mb |= 0x40
        extra = [enc_vel & 0xFF]
    out.append(mb)
    out += [d & 0xFF for d in dev]
    return out + extra


def open_phase_reconfig():
    cfg = [0x04,  # PM, SSTP, current model, no compensation, Casadei Table 1
           0x01,  # delay compensation
           0x08,  # torque mode
           0x48,  # speed loop every 10th period, 2000 lines
           0x00,  # encoder offset
           0x05,  # three current sensors, fault detection on, relays (0.1 ms)
           0x00,  # no raw patches
           0x00]  # session: 12-bit ADC, default T1PR and tick
    recs = []
    recs += record(32, [0, 0, 0, 0, 0]) * 2              # offset calibration, gates off
    recs += record(32, [0, 40, -40, 0, 0], scale=1, enc_vel=10)  # 1500 rpm, phase A open
    for _ in range(8):
        recs += record(32, [0, 40, -40, 0, 0], scale=1)
    for k in range(8):                                   # after it: three currents again
        recs += record(32, [40, -20 - k, -20 + k, 0, 0], scale=1)
    return bytes(cfg + recs)


def reversed_encoder_run():
    """An input the fuzzer found: a configuration whose raw patches set board.enc_reversed, run to
    RUN; the drive then reads enc_counts - 1 - count (app_enc.h), which the harness's conversion
    check must expect. Kept as a seed so that every slice runs it first."""
    return bytes.fromhex(
        "fae9e9e9e9e9e910000100e9e90165e9e9e9e9e9e9000000d30028d80000f8010028d80000f801000000000000000000"
        "00000000000000fe41003829fe000af8010028d80000f8010028d841414158b225414141414141414141414141414141"
        "413b414141464141000000000000006465616474696d655f636f6d7041414141414141414104")


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    d = sys.argv[1]
    shutil.rmtree(d, ignore_errors=True)
    os.makedirs(d)
    with open(os.path.join(d, "open_phase_reconfig"), "wb") as f:
        f.write(open_phase_reconfig())
    with open(os.path.join(d, "reversed_encoder_run"), "wb") as f:
        f.write(reversed_encoder_run())


if __name__ == "__main__":
    main()
