#!/usr/bin/python3
"""Cluster test (ctest label `cluster`): a real dask.distributed scheduler and two single-thread
workers on 127.0.0.1, a 40-run sweep sent through them with `dtc-sil sweep --dask`, one worker
killed while it holds work; the summary must equal a local sweep's row for row. Also: an
unreachable scheduler is refused before any run.

Usage: test_dask_sweep.py DTC_SIL_EXE SCENARIO WORKDIR
Every process this test starts is stopped at the end, pass or fail; the whole test is bounded by
DEADLINE_S (and by the ctest timeout).
"""
import os
import shutil
import signal
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools", "sweep"))
from local_cluster import LocalCluster, free_port  # noqa: E402

DEADLINE_S = 240.0


def main(exe, scenario, work):
    t0 = time.monotonic()

    def left():
        return max(1.0, DEADLINE_S - (time.monotonic() - t0))

    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    # 40 runs of 2 s simulated, one run per task: the sweep lasts long enough for a worker to be
    # killed while it holds tasks.
    axes = ["--grid", "control.speed_ref_rpm=300,600,900,1200,1500",
            "--sample", "sensors.current_noise_a_rms=uniform:0:0.02", "--n", "8", "--seed", "5",
            "--set", "duration_s=2.0", "--set", "metrics_window_s=0.2"]

    bad_dir = os.path.join(work, "bad")
    bad = subprocess.run([exe, "sweep", scenario, "--out", bad_dir, "--dask", f"tcp://127.0.0.1:{free_port()}"] + axes,
                         capture_output=True, text=True, timeout=left())
    assert bad.returncode == 1, (bad.returncode, bad.stderr)
    assert "cannot reach the scheduler" in bad.stderr, bad.stderr
    rows = os.path.join(bad_dir, "rows.jsonl")
    assert not os.path.exists(rows) or os.path.getsize(rows) == 0, "runs were made for an unreachable scheduler"

    local = subprocess.run([exe, "sweep", scenario, "--out", os.path.join(work, "local"), "--jobs", "2"] + axes,
                           capture_output=True, text=True, timeout=left())
    assert local.returncode == 0, local.stderr

    sweep = None
    with LocalCluster(os.path.join(work, "cluster"), n_workers=2) as cl:
        try:
            sweep = subprocess.Popen([exe, "sweep", scenario, "--out", os.path.join(work, "dask"), "--dask", cl.address,
                                      "--chunk", "1"] + axes, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                     text=True, start_new_session=True)
            killed = None
            while killed is None and sweep.poll() is None and time.monotonic() - t0 < DEADLINE_S:
                busy = [a for a, keys in cl.client.processing().items() if keys]
                if len(busy) == len(cl.worker_pids):
                    killed = busy[0]
                    os.kill(cl.worker_pids[killed], signal.SIGKILL)
                time.sleep(0.02)
            _, err = sweep.communicate(timeout=left())
        finally:
            if sweep is not None and sweep.poll() is None:
                os.killpg(sweep.pid, signal.SIGKILL)
                sweep.wait(timeout=10)
    assert killed is not None, "the sweep ended before a worker could be killed while holding work"
    assert sweep.returncode == 0, (sweep.returncode, err)
    with open(os.path.join(work, "local", "summary.csv")) as f:
        ref = f.read()
    with open(os.path.join(work, "dask", "summary.csv")) as f:
        got = f.read()
    assert ref.count("\n") == 41, ref.count("\n")
    assert got == ref, "the Dask sweep's summary differs from the local one"
    print(f"cluster: 40 runs through 2 workers, worker {killed} killed while busy; "
          f"summary identical to the local sweep ({time.monotonic() - t0:.1f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:4]))
